#pragma once
// The camera image of the structured-light sensor (paper section 3.1,
// Fig. 21): the scene's albedo under ambient light, the laser stripe, and an
// 8-bit colour sensor with auto exposure, noise and saturation. The stripe is
// rendered from the physics, not pasted from the geometric truth:
//
// - every pixel's camera ray meets a surface Q; Q receives laser light when
//   it lies within the sheet's Gaussian thickness, inside the fan, and the
//   emitter sees it (shadow ray), so occlusion works both ways here too;
// - laser irradiance at Q: P / (2 phi r) * sqrt(2 / pi) / w(r) *
//   exp(-2 d^2 / w(r)^2) * cos(incidence), with P the power in the fan, phi
//   its half angle, r the emitter range, d the distance from the sheet's
//   centre plane and w(r) = sqrt(w0^2 + (theta r)^2) the 1/e^2 half
//   thickness: the stripe dims with distance and grazing incidence and
//   widens with distance;
// - pixels near the sheet are integrated over their height (sub-rows), then
//   the laser layer is blurred by the lens's point spread function;
// - signals are in "lux on the surface times reflectance": ambient light of
//   E lux on a surface of reflectance rho gives rho * E in each channel (the
//   camera is white-balanced to the ambient light); the laser's red light
//   counts as red_lux_per_w_per_m2 lux per W/m^2, with small leaks into the
//   green and blue channels.
//
// Simulator output: none of these numbers is measured on Ragno's camera;
// each default says where it comes from.
#include <cstddef>
#include <cstdint>
#include <random>
#include <vector>

#include "stridemap/sim/structured_light_simulator.hpp"

namespace stridemap {

struct AmbientLight {
  /// Illuminance on a horizontal surface [lux]: about 50 in a dim lab, 300-500
  /// in a lit lab or office, 1000-5000 beside a window, 10^4-10^5 outdoors.
  double illuminance_lux = 300.0;
  /// Share of the light that arrives from all directions equally; the rest
  /// comes from straight above (ceiling lights, sky), so that vertical faces
  /// are darker than the floor. In [0, 1].
  double diffuse_fraction = 0.5;
  /// Reflectance of whatever a camera ray sees when it meets no surface of
  /// the scene within view_range_m (the lab's walls), lit by the diffuse part.
  double background_reflectance = 0.2;
  /// Camera rays end here [m].
  double view_range_m = 10.0;
};

struct LaserStripeOptions {
  /// Optical power leaving the line projector [W]. 1 mW: laser class 2, as
  /// in most line lasers of laser levels (Ragno's came from one).
  double power_w = 0.001;
  /// 1/e^2 half thickness of the sheet at the emitter [m] and its growth
  /// with range [rad]: 0.5 mm and 2 mrad give a line about 1.8 mm thick at
  /// 0.3 m, typical of such projectors.
  double half_thickness_m = 0.0005;
  double divergence_rad = 0.002;
  /// How many lux of (white-balanced) ambient light give the red channel the
  /// same signal as 1 W/m^2 of the laser's 650 nm light. Estimate: white
  /// light carries about 3.6 mW/m^2 per lux, a third of it in the red band,
  /// where the channel's response at 650 nm is about 0.8 of its average:
  /// 0.8 / 1.2e-3 = about 650.
  double red_lux_per_w_per_m2 = 650.0;
  /// Response of the green and blue channels to the laser relative to the
  /// red one (colour filter leakage of a Bayer sensor).
  double green_leak = 0.08;
  double blue_leak = 0.04;
};

struct CameraSensorOptions {
  /// Auto exposure brings the image's mean green signal to target_mean_dn;
  /// off: the gain is fixed_gain_dn_per_lux.
  bool auto_exposure = true;
  double target_mean_dn = 110.0;
  /// The longest exposure: auto exposure cannot raise the gain above what a
  /// grey (0.5) surface lit by this much needs to reach target_mean_dn, so a
  /// dim scene stays dark [lux].
  double auto_exposure_limit_lux = 150.0;
  /// Highlight protection of the auto exposure [DN]: when above 0, the gain
  /// is also held low enough that the brightest highlight_fraction of the
  /// pixels' ambient signal stays at or below this, so that a white object
  /// and the stripe on it are not clipped (cameras call it highlight
  /// priority metering). 220 DN by default: on grey scenes it never binds
  /// (the gain is the mean metering's), on white objects it keeps the stripe
  /// detectable (docs/structured_light_images.md). 0: the mean only.
  double highlight_limit_dn = 220.0;
  double highlight_fraction = 0.01;
  /// Gain with auto exposure off [DN per lux times reflectance]: 0.8 puts a
  /// grey surface at 300 lux at 120 of 255.
  double fixed_gain_dn_per_lux = 0.8;
  /// Photo-electrons per digital number: shot noise has a standard deviation
  /// of sqrt(signal * this) / this DN. 8 e-/DN: a full well of about 2000 e-
  /// at 255, a small webcam pixel.
  double electrons_per_dn = 8.0;
  /// Read noise [DN], Gaussian, added to each channel.
  double read_noise_dn = 1.0;
  /// Standard deviation of the lens's point spread function [px]: a webcam
  /// lens at VGA blurs a sharp line to about 2.4 px (full width at half
  /// maximum), the "profile of a few pixels" the detector sees.
  double psf_sigma_px = 1.0;
  /// Sub-rows per pixel where the sheet passes (>= 1): the stripe can be
  /// thinner than a pixel.
  int sub_rows = 4;
  bool enable_noise = true;
};

struct StripeImageOptions {
  AmbientLight ambient;
  LaserStripeOptions laser;
  CameraSensorOptions camera;

  /// Throws InputError "structured light image options: <field>: <problem>".
  void validate() const;
};

/// What the renderer did on one frame.
struct StripeImageStats {
  double gain_dn_per_lux = 0.0;       ///< exposure chosen (or fixed)
  double mean_green_signal_lux = 0.0; ///< mean of the green channel's signal before the gain
  double peak_laser_signal_lux = 0.0; ///< strongest red laser signal on a pixel (after the blur)
  std::size_t saturated_pixels = 0;   ///< pixels with at least one channel clipped at 255
  std::size_t laser_pixels = 0;       ///< pixels whose laser signal reaches 1 DN
};

class StructuredLightImageRenderer {
 public:
  /// Copies the scene. The geometry options (fan, range) are shared with the
  /// geometric simulator that gives the truth. Throws InputError for
  /// unusable parameters or options.
  StructuredLightImageRenderer(const Scene& scene, const StructuredLightParameters& parameters,
                               const StripeImageOptions& options = {},
                               const StructuredLightSimOptions& geometry = {}, std::uint64_t seed = 1);

  /// Renders the image seen from the TRUE pose into `rgb`: resized to
  /// 3 * R_hor * R_ver bytes, row-major, top row first, (R, G, B) per pixel,
  /// which is io::RgbImage's layout. Frame k (from construction or reset)
  /// draws its noise from a generator seeded by (seed, k) only. `truth`, if
  /// given, gets the geometric simulator's answer for the same pose (its
  /// row noise option applies only there). Throws InputError for a pose with
  /// a non-finite field.
  StripeImageStats render(const TrunkPose& pose, std::vector<std::uint8_t>& rgb,
                          StructuredLightFrameTruth* truth = nullptr);

  /// The last frame's laser light on pixel (u_px, v_px), column and row
  /// from the top left: its red signal before noise [DN at the frame's
  /// gain], and that over the standard deviation of the red channel's shot
  /// and read noise there. A truth that needs no detector: where the laser
  /// light is in the image, wherever the sheet's one stripe per column (the
  /// geometric truth) puts it. 0 outside the image or before the first
  /// frame.
  double laser_signal_dn(int u_px, int v_px) const;
  double laser_signal_to_noise(int u_px, int v_px) const;

  /// Changes the light between frames (the lighting experiment).
  void set_ambient(const AmbientLight& ambient);
  void reset(std::uint64_t seed);

  const StripeImageOptions& options() const { return options_; }
  const StructuredLightModel& model() const { return geometry_.model(); }
  const StructuredLightSimulator& geometry() const { return geometry_; }

 private:
  struct SurfaceSample {
    Eigen::Vector3d point = Eigen::Vector3d::Zero();
    Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
    double reflectance = 0.0;
    bool hit = false;
  };
  SurfaceSample sample(const StructuredLightSensorPose& sensor, double u_px, double v_px) const;
  /// Laser irradiance on the sample's surface [W/m^2] (0 when unlit).
  double laser_irradiance(const StructuredLightSensorPose& sensor, const SurfaceSample& s) const;
  /// The last frame's index of pixel (u_px, v_px), -1 outside the image or
  /// before the first frame.
  std::ptrdiff_t last_frame_pixel(int u_px, int v_px) const;

  StructuredLightSimulator geometry_;
  StripeImageOptions options_;
  std::uint64_t seed_ = 0;
  std::uint64_t frame_index_ = 0;
  double last_gain_dn_per_lux_ = 0.0;
  std::mt19937_64 rng_;
  // Per-frame scratch, sized once.
  std::vector<SurfaceSample> samples_;
  std::vector<float> highlight_scratch_;
  std::vector<float> ambient_, sheet_distance_m_, half_thickness_m_, laser_, blurred_, blur_scratch_;
};

}  // namespace stridemap
