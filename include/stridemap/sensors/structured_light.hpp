#pragma once
// Structured-light sensor model (paper section 3.1, eq. 1 and 2): a camera
// and a laser-sheet emitter. A stripe pixel (u, v) is back-projected onto
// the sheet to a point (x_c, y_c, z_c) of the camera frame.
//
// Conventions (docs/structured_light.md has the derivation):
// - Camera frame C as printed in eq. (1): z_c along the optical axis, y_c
//   down in the image, x_c towards the image's LEFT edge (u = 0 gives
//   x_c > 0). With u counted from the left column this frame is
//   left-handed; camera_to_sensor_frame() maps it to the right-handed
//   sensor frame (forward, left, up) of core.
// - u, v are continuous image coordinates in pixels from the top-left corner
//   of the image region: u = 0 is the left edge, v = 0 the top edge,
//   v = R_ver the bottom edge; the centre of pixel (column i, row k) is
//   (i + 0.5, k + 0.5) and the principal point is (R_hor / 2, R_ver / 2).
// - The emitter lies on the y_c axis, b above the optical centre
//   (y_c = -b, z_c = 0). beta is the angle between that baseline and the
//   sheet, so the sheet y_c = z_c cot(beta) - b descends 90 deg - beta below
//   the optical axis and crosses it at z_c = b tan(beta).
// - A pixel whose ray is parallel to the sheet (eq. 1's denominator zero, up
//   to a relative 1e-12 of rounding) or meets it behind the camera has no
//   point: the model reports it (StripePointStatus), never NaN.
#include <cstdint>
#include <numbers>
#include <optional>
#include <string>

#include <Eigen/Core>

#include "stridemap/core/pose.hpp"

namespace stridemap {

/// Geometry of the camera-emitter pair, its mount on the trunk and the error
/// bounds of eq. (8). Defaults are the Ragno sensor of section 3.3.
struct StructuredLightParameters {
  /// b: distance from the camera's optical centre to the emitter, along the
  /// camera's vertical image axis (the emitter is above the camera); up to
  /// 10 m [m].
  double baseline_m = 0.120;
  /// beta: angle between the baseline and the laser sheet, strictly between
  /// 0 and 90 deg; smaller angles point the sheet more steeply down [rad].
  double sheet_angle_rad = 45.0 * std::numbers::pi / 180.0;
  /// tau_c: half the vertical viewing angle of the image region (eq. 2) [rad].
  double half_fov_vertical_rad = 28.14 * std::numbers::pi / 180.0;
  /// gamma_c: half the horizontal viewing angle of the image region [rad].
  double half_fov_horizontal_rad = 38.8 * std::numbers::pi / 180.0;
  /// R_hor: width of the image region that tau_c / gamma_c describe [px].
  /// The paper does not state Ragno's; 640 (VGA) is assumed.
  int image_width_px = 640;
  /// R_ver: height of that region [px]. 480 assumed for Ragno.
  int image_height_px = 480;
  /// Camera on the trunk: pitch_rad is alpha (positive towards the ground,
  /// strictly between -90 and 90 deg), height_m the optical centre's height
  /// above the ground in the neutral posture (> 0). Ragno: 10 deg, 0.174 m.
  SensorMount mount{0.174, 10.0 * std::numbers::pi / 180.0, 0.0, 0.0};

  /// Delta b of eq. (8): error bound of the calibrated baseline [m]. The
  /// paper takes it from calibration [14] without giving a number; 1 mm is
  /// a placeholder of the right order for a hand-built rig.
  double baseline_error_m = 0.001;
  /// Delta beta of eq. (8) [rad]. Placeholder 0.25 deg.
  double sheet_angle_error_rad = 0.25 * std::numbers::pi / 180.0;
  /// Delta tau_c of eq. (8) [rad]. Placeholder 0.1 deg (camera calibration
  /// gives the focal length to a fraction of a percent).
  double half_fov_vertical_error_rad = 0.1 * std::numbers::pi / 180.0;
  /// Delta v of eq. (8): error of the stripe's row in the image [px];
  /// 0.5 px is the quantisation of a whole-pixel detector.
  double row_error_px = 0.5;
  /// Delta u: error of the column [px], used only by the x_c uncertainty
  /// maps of Fig. 3 (eq. 8 does not depend on u).
  double column_error_px = 0.5;

  /// What is wrong with a set, for messages: `field` is the member's name
  /// ("sheet_angle_rad", "mount.height_m"), `what` says what is wrong
  /// (angles in degrees, lengths in metres).
  struct Problem {
    std::string field;
    std::string what;
  };
  /// The first problem found, or nothing when the set is usable.
  std::optional<Problem> first_problem() const;
  /// Throws InputError "structured light parameters: <field>: <what>".
  void validate() const;
};

/// Eq. (2): the half viewing angle atan(R / (2 f)) of an image side of
/// R pixels seen through a focal length of f pixels.
double half_fov_from_focal_length_rad(double image_size_px, double focal_length_px);
/// Eq. (2) inverted: the focal length R / (2 tan(half angle)) in pixels.
double focal_length_from_half_fov_px(double image_size_px, double half_fov_rad);

enum class StripePointStatus : std::uint8_t {
  valid,
  not_finite,       ///< u or v is NaN or infinite, or the point too far to represent
  outside_image,    ///< u outside [0, R_hor] or v outside [0, R_ver]
  no_intersection,  ///< the pixel's ray is parallel to the sheet or meets it behind the camera
};

/// "valid", "not finite", "outside the image", "no intersection with the sheet".
const char* to_string(StripePointStatus status);

/// A back-projected point and its partial derivatives (each a column of
/// d(x_c, y_c, z_c)/d parameter).
struct CameraPointPartials {
  Eigen::Vector3d point = Eigen::Vector3d::Zero();                  ///< (x_c, y_c, z_c) [m]
  Eigen::Vector3d d_baseline = Eigen::Vector3d::Zero();             ///< per m of b
  Eigen::Vector3d d_sheet_angle = Eigen::Vector3d::Zero();          ///< per rad of beta
  Eigen::Vector3d d_half_fov_vertical = Eigen::Vector3d::Zero();    ///< per rad of tau_c
  Eigen::Vector3d d_half_fov_horizontal = Eigen::Vector3d::Zero();  ///< per rad of gamma_c
  Eigen::Vector3d d_row = Eigen::Vector3d::Zero();                  ///< per px of v [m/px]
  Eigen::Vector3d d_column = Eigen::Vector3d::Zero();               ///< per px of u [m/px]
};

/// Eq. (1) with the trigonometry of the parameters computed once.
class StructuredLightModel {
 public:
  /// Throws InputError (see StructuredLightParameters::validate).
  explicit StructuredLightModel(const StructuredLightParameters& parameters = {});

  const StructuredLightParameters& parameters() const { return parameters_; }

  /// Eq. (1). `point` is written only when the result is valid.
  StripePointStatus back_project(double u_px, double v_px, Eigen::Vector3d& point) const;
  /// Eq. (1) with the analytic derivatives; `out` is written only when valid.
  StripePointStatus back_project(double u_px, double v_px, CameraPointPartials& out) const;

  /// The pixel (u, v) at which the camera sees a camera-frame point (the
  /// pinhole projection that eq. 1 inverts). Nothing when the point is not
  /// in front of the camera (z_c <= 0) or not finite. The image bounds and
  /// the sheet are not checked: see in_image() and distance_from_sheet_m().
  std::optional<Eigen::Vector2d> project(const Eigen::Vector3d& camera_point) const;

  /// True when 0 <= u <= R_hor and 0 <= v <= R_ver.
  bool in_image(double u_px, double v_px) const;

  /// Signed distance of a camera-frame point from the laser sheet, positive
  /// on the camera's side [m].
  double distance_from_sheet_m(const Eigen::Vector3d& camera_point) const;

  /// z_c at which row v sees the sheet, or nothing when it does not.
  std::optional<double> sheet_depth_at_row_m(double v_px) const;
  /// The row that sees the sheet at depth z_c > 0 (may lie outside the image).
  double row_at_sheet_depth_px(double depth_m) const;
  /// The row where the sheet recedes to infinity (eq. 1's denominator is
  /// zero): R_ver / 2 (1 + cot(beta) / tan(tau_c)). Rows below it see no sheet.
  double vanishing_row_px() const;

  double tan_half_fov_vertical() const { return tan_tau_; }
  double tan_half_fov_horizontal() const { return tan_gamma_; }
  double cot_sheet_angle() const { return cot_beta_; }

 private:
  StripePointStatus check_pixel(double u_px, double v_px) const;
  /// Eq. (1)'s denominator D = n_v tan(tau_c) + cot(beta) is positive and
  /// not zero up to rounding.
  bool meets_sheet(double denominator) const;

  StructuredLightParameters parameters_;
  double tan_tau_ = 0.0, tan_gamma_ = 0.0, cot_beta_ = 0.0;
  double sin_beta_ = 0.0, cos_beta_ = 0.0;
  double dcot_dbeta_ = 0.0, dtan_dtau_ = 0.0, dtan_dgamma_ = 0.0;
  double width_ = 0.0, height_ = 0.0;
};

/// Camera frame C (x_c left, y_c down, z_c ahead) to the sensor frame S of
/// core/sensor_transform.hpp (x ahead, y left, z up), before the mount's
/// pitch: (z_c, x_c, -y_c).
inline Eigen::Vector3d camera_to_sensor_frame(const Eigen::Vector3d& camera_point) {
  return {camera_point.z(), camera_point.x(), -camera_point.y()};
}

}  // namespace stridemap
