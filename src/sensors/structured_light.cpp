#include "stridemap/sensors/structured_light.hpp"

#include <cmath>
#include <cstdio>

#include "stridemap/core/error.hpp"

namespace stridemap {
namespace {

constexpr double kRadToDeg = 180.0 / std::numbers::pi;
constexpr double kRightAngle = std::numbers::pi / 2.0;
// Far beyond any camera; keeps 2 v / R_ver exact and the products finite.
constexpr int kMaxImageSide_px = 1000000;
// A denominator this small relative to its terms is zero up to rounding
// (tan and cot of 45 deg are not exactly 1): the ray runs along the sheet,
// and a "point" 1e12 baselines away would be rounding noise.
constexpr double kParallelTolerance = 1e-12;
// A camera and an emitter this far apart are not one sensor; a larger value
// is almost always millimetres written as metres.
constexpr double kMaxBaseline_m = 10.0;

std::string number_text(double value) {
  char text[48];
  std::snprintf(text, sizeof text, "%.6g", value);
  return text;
}

using Problem = StructuredLightParameters::Problem;

std::optional<Problem> positive_length(double value, const char* field) {
  if (std::isfinite(value) && value > 0.0) return std::nullopt;
  return Problem{field, "must be a positive number of metres, got " + number_text(value)};
}

std::optional<Problem> baseline_length(double value) {
  if (std::isfinite(value) && value > 0.0 && value <= kMaxBaseline_m) return std::nullopt;
  return Problem{"baseline_m", "must be a positive number of metres up to " + number_text(kMaxBaseline_m) +
                                   " (is it in millimetres?), got " + number_text(value)};
}

std::optional<Problem> open_angle(double value_rad, double low_deg, double high_deg, const char* field) {
  const double deg = value_rad * kRadToDeg;
  if (std::isfinite(value_rad) && deg > low_deg && deg < high_deg) return std::nullopt;
  return Problem{field, "must lie strictly between " + number_text(low_deg) + " and " + number_text(high_deg) +
                            " deg, got " + number_text(deg) + " deg"};
}

std::optional<Problem> image_side(int value, const char* field) {
  if (value >= 1 && value <= kMaxImageSide_px) return std::nullopt;
  return Problem{field, "must be a whole number of pixels from 1 to " + std::to_string(kMaxImageSide_px) + ", got " +
                            std::to_string(value)};
}

// `scale` converts the value into the unit shown (degrees for angles).
std::optional<Problem> error_bound(double value, double scale, const char* unit, const char* field) {
  if (std::isfinite(value) && value >= 0.0) return std::nullopt;
  return Problem{field, "must be a number >= 0, got " + number_text(value * scale) + " " + unit};
}

}  // namespace

std::optional<Problem> StructuredLightParameters::first_problem() const {
  const std::optional<Problem> checks[] = {
      baseline_length(baseline_m),
      open_angle(sheet_angle_rad, 0.0, 90.0, "sheet_angle_rad"),
      open_angle(half_fov_vertical_rad, 0.0, 90.0, "half_fov_vertical_rad"),
      open_angle(half_fov_horizontal_rad, 0.0, 90.0, "half_fov_horizontal_rad"),
      image_side(image_width_px, "image_width_px"),
      image_side(image_height_px, "image_height_px"),
      positive_length(mount.height_m, "mount.height_m"),
      open_angle(mount.pitch_rad, -90.0, 90.0, "mount.pitch_rad"),
      std::isfinite(mount.forward_offset_m)
          ? std::nullopt
          : std::optional<Problem>(Problem{"mount.forward_offset_m", "must be a finite number of metres"}),
      std::isfinite(mount.lateral_offset_m)
          ? std::nullopt
          : std::optional<Problem>(Problem{"mount.lateral_offset_m", "must be a finite number of metres"}),
      std::isfinite(mount.roll_rad)
          ? std::nullopt
          : std::optional<Problem>(Problem{"mount.roll_rad", "must be a finite angle"}),
      std::isfinite(mount.yaw_rad)
          ? std::nullopt
          : std::optional<Problem>(Problem{"mount.yaw_rad", "must be a finite angle"}),
      error_bound(baseline_error_m, 1.0, "m", "baseline_error_m"),
      error_bound(sheet_angle_error_rad, kRadToDeg, "deg", "sheet_angle_error_rad"),
      error_bound(half_fov_vertical_error_rad, kRadToDeg, "deg", "half_fov_vertical_error_rad"),
      error_bound(row_error_px, 1.0, "px", "row_error_px"),
      error_bound(column_error_px, 1.0, "px", "column_error_px"),
  };
  for (const auto& check : checks) {
    if (check) return check;
  }
  return std::nullopt;
}

void StructuredLightParameters::validate() const {
  if (const auto problem = first_problem()) {
    throw InputError("structured light parameters: " + problem->field + ": " + problem->what);
  }
}

double half_fov_from_focal_length_rad(double image_size_px, double focal_length_px) {
  if (!(std::isfinite(image_size_px) && image_size_px > 0.0 && std::isfinite(focal_length_px) &&
        focal_length_px > 0.0)) {
    throw InputError("eq. (2): image size and focal length must be positive pixel counts, got " +
                     number_text(image_size_px) + " and " + number_text(focal_length_px));
  }
  return std::atan(image_size_px / (2.0 * focal_length_px));
}

double focal_length_from_half_fov_px(double image_size_px, double half_fov_rad) {
  if (!(std::isfinite(image_size_px) && image_size_px > 0.0 && half_fov_rad > 0.0 && half_fov_rad < kRightAngle)) {
    throw InputError("eq. (2): need an image size > 0 px and a half angle strictly between 0 and 90 deg, got " +
                     number_text(image_size_px) + " px and " + number_text(half_fov_rad * kRadToDeg) + " deg");
  }
  return image_size_px / (2.0 * std::tan(half_fov_rad));
}

const char* to_string(StripePointStatus status) {
  switch (status) {
    case StripePointStatus::valid: return "valid";
    case StripePointStatus::not_finite: return "not finite";
    case StripePointStatus::outside_image: return "outside the image";
    case StripePointStatus::no_intersection: return "no intersection with the sheet";
  }
  return "unknown";
}

StructuredLightModel::StructuredLightModel(const StructuredLightParameters& parameters) : parameters_(parameters) {
  parameters_.validate();
  tan_tau_ = std::tan(parameters_.half_fov_vertical_rad);
  tan_gamma_ = std::tan(parameters_.half_fov_horizontal_rad);
  sin_beta_ = std::sin(parameters_.sheet_angle_rad);
  cos_beta_ = std::cos(parameters_.sheet_angle_rad);
  cot_beta_ = cos_beta_ / sin_beta_;
  // Derivatives of the trigonometric terms, for the partials.
  dcot_dbeta_ = -1.0 / (sin_beta_ * sin_beta_);
  dtan_dtau_ = 1.0 + tan_tau_ * tan_tau_;
  dtan_dgamma_ = 1.0 + tan_gamma_ * tan_gamma_;
  width_ = parameters_.image_width_px;
  height_ = parameters_.image_height_px;
}

bool StructuredLightModel::meets_sheet(double denominator) const {
  return denominator > kParallelTolerance * (tan_tau_ + cot_beta_);
}

bool StructuredLightModel::in_image(double u_px, double v_px) const {
  return u_px >= 0.0 && u_px <= width_ && v_px >= 0.0 && v_px <= height_;
}

StripePointStatus StructuredLightModel::check_pixel(double u_px, double v_px) const {
  if (!std::isfinite(u_px) || !std::isfinite(v_px)) return StripePointStatus::not_finite;
  if (!in_image(u_px, v_px)) return StripePointStatus::outside_image;
  return StripePointStatus::valid;
}

StripePointStatus StructuredLightModel::back_project(double u_px, double v_px, Eigen::Vector3d& point) const {
  if (const auto status = check_pixel(u_px, v_px); status != StripePointStatus::valid) return status;
  const double row_factor = 1.0 - 2.0 * v_px / height_;    // +1 at the top edge, -1 at the bottom
  const double column_factor = 1.0 - 2.0 * u_px / width_;  // +1 at the left edge
  const double denominator = row_factor * tan_tau_ + cot_beta_;
  // A zero or negative denominator: the ray climbs no faster than the sheet
  // (parallel) or meets its extension behind the camera.
  if (!meets_sheet(denominator)) return StripePointStatus::no_intersection;
  const double z = parameters_.baseline_m / denominator;
  point = {z * column_factor * tan_gamma_, z * cot_beta_ - parameters_.baseline_m, z};
  // A ray that meets the sheet almost at infinity (viewing angles of a
  // fraction of a degree) can still overflow.
  return point.allFinite() ? StripePointStatus::valid : StripePointStatus::not_finite;
}

StripePointStatus StructuredLightModel::back_project(double u_px, double v_px, CameraPointPartials& out) const {
  if (const auto status = check_pixel(u_px, v_px); status != StripePointStatus::valid) return status;
  const double b = parameters_.baseline_m;
  const double row_factor = 1.0 - 2.0 * v_px / height_;
  const double column_factor = 1.0 - 2.0 * u_px / width_;
  const double denominator = row_factor * tan_tau_ + cot_beta_;
  if (!meets_sheet(denominator)) return StripePointStatus::no_intersection;

  // z = b / D with D = n_v tan(tau) + cot(beta); every parameter but b and
  // gamma acts through D, so dz/dp = -(z / D) dD/dp.
  const double z = b / denominator;
  const double dz_dD = -z / denominator;
  const double dcot_dbeta = dcot_dbeta_;
  const double z_b = 1.0 / denominator;
  const double z_beta = dz_dD * dcot_dbeta;
  const double z_tau = dz_dD * row_factor * dtan_dtau_;
  const double z_v = dz_dD * (-2.0 * tan_tau_ / height_);

  // y = z cot(beta) - b (the sheet's equation), x = z n_u tan(gamma).
  const double lateral = column_factor * tan_gamma_;
  out.point = {z * lateral, z * cot_beta_ - b, z};
  out.d_baseline = {z_b * lateral, z_b * cot_beta_ - 1.0, z_b};
  out.d_sheet_angle = {z_beta * lateral, z_beta * cot_beta_ + z * dcot_dbeta, z_beta};
  out.d_half_fov_vertical = {z_tau * lateral, z_tau * cot_beta_, z_tau};
  out.d_half_fov_horizontal = {z * column_factor * dtan_dgamma_, 0.0, 0.0};
  out.d_row = {z_v * lateral, z_v * cot_beta_, z_v};
  out.d_column = {z * (-2.0 / width_) * tan_gamma_, 0.0, 0.0};
  return out.point.allFinite() ? StripePointStatus::valid : StripePointStatus::not_finite;
}

std::optional<Eigen::Vector2d> StructuredLightModel::project(const Eigen::Vector3d& camera_point) const {
  if (!camera_point.allFinite() || !(camera_point.z() > 0.0)) return std::nullopt;
  const double u = 0.5 * width_ * (1.0 - camera_point.x() / (camera_point.z() * tan_gamma_));
  const double v = 0.5 * height_ * (1.0 + camera_point.y() / (camera_point.z() * tan_tau_));
  if (!std::isfinite(u) || !std::isfinite(v)) return std::nullopt;
  return Eigen::Vector2d(u, v);
}

double StructuredLightModel::distance_from_sheet_m(const Eigen::Vector3d& camera_point) const {
  // Unit normal (0, sin beta, -cos beta); the camera (origin) is at +b sin(beta).
  return sin_beta_ * (camera_point.y() + parameters_.baseline_m) - cos_beta_ * camera_point.z();
}

std::optional<double> StructuredLightModel::sheet_depth_at_row_m(double v_px) const {
  if (!std::isfinite(v_px)) return std::nullopt;
  const double denominator = (1.0 - 2.0 * v_px / height_) * tan_tau_ + cot_beta_;
  if (!meets_sheet(denominator)) return std::nullopt;
  return parameters_.baseline_m / denominator;
}

double StructuredLightModel::row_at_sheet_depth_px(double depth_m) const {
  // Eq. (1)'s first line solved for v.
  const double row_factor = (parameters_.baseline_m / depth_m - cot_beta_) / tan_tau_;
  return 0.5 * height_ * (1.0 - row_factor);
}

double StructuredLightModel::vanishing_row_px() const { return 0.5 * height_ * (1.0 + cot_beta_ / tan_tau_); }

}  // namespace stridemap
