#pragma once
// Geometric structured-light simulator: where the laser sheet lights a scene
// and where the camera sees that light, per image column, with ground-truth
// labels (paper section 3, Fig. 5). The image renderer
// (sim/structured_light_image.hpp) draws the picture from the same geometry;
// this class gives the true stripe that a perfect detector would report.
//
// Why one candidate per column: the emitter sits on the camera's y_c axis
// (structured_light.hpp), so it lies in the plane through the optical centre
// of every image column. That plane cuts the sheet in one emitter ray; the
// first surface that ray meets is the only lit point the column can show.
// So:
// - the sheet cannot light what is hidden from the emitter: surfaces behind
//   the first hit of the column's emitter ray stay dark;
// - the camera cannot see what is hidden from it: the lit point is kept
//   only when the ray from the optical centre to it meets nothing before it
//   and the surface faces the camera.
//
// Frames: the scene and the pose are in the map frame (core/pose.hpp); the
// camera frame C and pixel conventions are those of structured_light.hpp;
// the whole sensor (camera and emitter) is tilted by mount.pitch_rad as in
// eq. (5).
//
// Usage (one frame per trunk pose, for TerrainMapper::integrate_points):
//
//   StructuredLightSimulator sim(scene, parameters, {}, seed);
//   StructuredLightFrameTruth frame;          // reused: no allocation per frame once grown
//   sim.simulate(true_pose, frame);
//   stripe_to_map_points(sim.model(), frame.stripe, pose_estimate, mapper.motion_to(pose_estimate),
//                        mapper.options().update, points);
#include <cstddef>
#include <cstdint>
#include <numbers>
#include <random>
#include <vector>

#include <Eigen/Core>

#include "stridemap/core/pose.hpp"
#include "stridemap/sensors/structured_light.hpp"
#include "stridemap/sensors/structured_light_mapping.hpp"
#include "stridemap/sim/scene.hpp"
#include "stridemap/sim/scene_ray_caster.hpp"

namespace stridemap {

/// What happened in one image column; the detector never sees it.
enum class StripeColumnLabel : std::uint8_t {
  visible,             ///< the sheet lights a surface the camera sees: u_px, v_px are the true stripe
  no_surface,          ///< the column's emitter ray meets nothing within max_range_m
  hidden_from_camera,  ///< the lit point is hidden from the camera, or its surface faces away
  outside_image,       ///< the lit point is seen above or below the image (or behind the camera)
  outside_fan,         ///< the column's emitter ray lies outside the projector's fan
};

/// "visible", "no surface", "hidden from the camera", "outside the image",
/// "outside the fan".
const char* to_string(StripeColumnLabel label);

/// Ground truth of one image column. Fields after `label` are meaningful as
/// stated on each; otherwise they keep their defaults.
struct StripeColumnTruth {
  StripeColumnLabel label = StripeColumnLabel::no_surface;
  /// The true stripe centre in continuous image coordinates (the column's
  /// centre i + 0.5, and the sub-pixel row). visible and outside_image.
  double u_px = 0.0;
  double v_px = 0.0;
  /// The lit point in the map frame and in the camera frame C; its surface
  /// normal (unit, outward), reflectance and object (RayHit's convention:
  /// -1 terrain, then boxes, then cylinders). All labels but no_surface and
  /// outside_fan.
  Eigen::Vector3d point_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d camera_point_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
  double reflectance = 0.0;
  int object_index = -1;
  double emitter_range_m = 0.0;  ///< emitter to the lit point [m]
  double camera_range_m = 0.0;   ///< optical centre to the lit point [m]
  /// Cosine of the angle between the surface normal and the direction to
  /// the emitter (laser incidence) and to the camera (viewing angle).
  double cos_incidence = 0.0;
  double cos_view = 0.0;
};

struct StructuredLightSimOptions {
  /// Emitter rays light nothing beyond this range [m]: the stripe is too
  /// faint to see there. 2 m is about ten times Ragno's ground range.
  double max_range_m = 2.0;
  /// Half the fan angle of the line projector, measured in the sheet from
  /// its centre ray (the one in the camera's y_c-z_c plane) [rad], in
  /// (0, 90) deg. 45 deg covers the whole image width of Ragno (29.6 deg
  /// needed) and of Fig. 3's configuration.
  double fan_half_angle_rad = 45.0 * std::numbers::pi / 180.0;
  /// Standard deviation of Gaussian noise added to the row of each visible
  /// column in `StructuredLightFrameTruth::stripe` [px], standing in for a
  /// detector when the image path is not simulated. 0 (default): the exact
  /// rows. The truth in `columns` never carries noise.
  double row_noise_sigma_px = 0.0;
  /// The camera's ray to the lit point may stop this much short of it and
  /// still count as reaching it [m]; absorbs rounding of the ray casts.
  double occlusion_tolerance_m = 1e-4;

  /// Throws InputError "structured light simulator options: <field>: <problem>".
  void validate() const;
};

/// Where the sensor is in the map frame for one trunk pose.
struct StructuredLightSensorPose {
  Eigen::Vector3d camera_origin_m = Eigen::Vector3d::Zero();   ///< optical centre
  Eigen::Vector3d emitter_origin_m = Eigen::Vector3d::Zero();  ///< b above it along -y_c
  /// Columns are the camera frame's x_c, y_c, z_c axes in the map frame.
  /// The camera frame is left-handed (structured_light.hpp), so this matrix
  /// has determinant -1: use it to map directions and points, not as a
  /// rotation of the right-handed kind.
  Eigen::Matrix3d camera_axes_in_map = Eigen::Matrix3d::Identity();
  /// Unit normal of the laser sheet in the map frame, pointing to the
  /// camera's side; sheet_offset_m makes normal . p + offset = 0 on the sheet.
  Eigen::Vector3d sheet_normal = Eigen::Vector3d::UnitZ();
  double sheet_offset_m = 0.0;

  /// Map-frame point in the camera frame C.
  Eigen::Vector3d to_camera(const Eigen::Vector3d& map_point) const {
    return camera_axes_in_map.transpose() * (map_point - camera_origin_m);
  }
  /// Signed distance of a map-frame point from the sheet, positive on the
  /// camera's side [m].
  double sheet_distance_m(const Eigen::Vector3d& map_point) const {
    return sheet_normal.dot(map_point) + sheet_offset_m;
  }
};

/// One simulated frame.
struct StructuredLightFrameTruth {
  /// One entry per image column, left to right (R_hor entries).
  std::vector<StripeColumnTruth> columns;
  /// The visible columns' (u, v), left to right, with the option's row
  /// noise: what a detector would hand to stripe_to_map_points.
  std::vector<StripePixel> stripe;
  StructuredLightSensorPose sensor;
  std::size_t visible = 0, no_surface = 0, hidden_from_camera = 0, outside_image = 0, outside_fan = 0;
};

class StructuredLightSimulator {
 public:
  /// Copies the scene. Throws InputError for unusable parameters, options
  /// or scene.
  StructuredLightSimulator(const Scene& scene, const StructuredLightParameters& parameters,
                           const StructuredLightSimOptions& options = {}, std::uint64_t seed = 1);

  /// Simulates one frame from the TRUE pose (the mount is
  /// parameters.mount). Frame k (counting from 0 since construction or
  /// reset) draws its row noise from a generator seeded by (seed, k) only.
  /// Reuses `out`'s storage. Throws InputError for a pose with a non-finite
  /// field.
  void simulate(const TrunkPose& pose, StructuredLightFrameTruth& out);

  /// The sensor's place for a pose (no scene needed).
  StructuredLightSensorPose sensor_pose(const TrunkPose& pose) const;

  /// Restarts the frame counter with a new seed.
  void reset(std::uint64_t seed);
  std::uint64_t frames_simulated() const { return frame_index_; }

  const StructuredLightModel& model() const { return model_; }
  const StructuredLightSimOptions& options() const { return options_; }
  const SceneRayCaster& ray_caster() const { return caster_; }
  const Scene& scene() const { return caster_.scene(); }

 private:
  SceneRayCaster caster_;
  StructuredLightModel model_;
  StructuredLightSimOptions options_;
  std::uint64_t seed_ = 0;
  std::uint64_t frame_index_ = 0;
  std::mt19937_64 rng_;
};

/// The emitter ray of image column u (continuous coordinate) in the camera
/// frame: unit direction from the emitter at (0, -b, 0) within the sheet
/// and the column's plane.
Eigen::Vector3d column_emitter_direction(const StructuredLightModel& model, double u_px);

/// Bijective 64-bit mixer for per-frame seeds (splitmix64's finaliser).
std::uint64_t mix_seed(std::uint64_t x);

}  // namespace stridemap
