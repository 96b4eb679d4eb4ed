#pragma once
// The generic point source: points already measured in the sensor's own
// frame (a depth camera, a stereo pair, a 3D lidar's sweep) with a height
// sigma per point. Its error model is that sigma scaled to a worst-case
// bound, plus what the trunk's pitch and roll errors do to a point that far
// away. The travel term uses the inclination of the sensor's x-y plane, as
// for a 2D scanner mounted the same way.
//
// Sensor frame S as for the laser (core/sensor_transform.hpp): x ahead,
// y left, z up before the mount's pitch tilts it.
#include <cstddef>
#include <span>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "stridemap/pipeline/sensor_model.hpp"

namespace stridemap {

struct PointCloudSensorOptions {
  /// Delta z of a point = sigma_scale x its sigma (3: the 99.7 % bound of a
  /// Gaussian error, as the paper's bounds are worst cases).
  double sigma_scale = 3.0;
};

/// One frame of the point source.
struct PointFrame {
  double time_s = 0.0;
  std::vector<Eigen::Vector3d> points_m;  ///< sensor frame [m]
  std::vector<double> height_sigma_m;     ///< one per point [m]
};

struct PointConversionStats {
  std::size_t points = 0;
  std::size_t converted = 0;
  std::size_t not_finite = 0;  ///< a coordinate or the sigma NaN / infinite, or the sigma negative

  PointConversionStats& operator+=(const PointConversionStats& other) {
    points += other.points;
    converted += other.converted;
    not_finite += other.not_finite;
    return *this;
  }
};

class PointCloudSensor final : public SensorModel {
 public:
  /// Throws InputError unless sigma_scale is a positive number.
  explicit PointCloudSensor(const PointCloudSensorOptions& options = {});

  std::string_view name() const override { return "points"; }
  /// The frame the next to_points() converts. Throws InputError naming the
  /// frame's time when the two lists differ in length. The spans must stay
  /// valid until to_points().
  void set_frame(double time_s, std::span<const Eigen::Vector3d> points_m, std::span<const double> height_sigma_m);
  void to_points(const TrunkPose& pose, const SensorMount& mount, const UpdateOptions& update,
                 PointBatch& batch) override;

  /// Of the frame converted last.
  const PointConversionStats& last_stats() const { return last_; }

 private:
  PointCloudSensorOptions options_;
  std::span<const Eigen::Vector3d> points_;
  std::span<const double> sigma_;
  PointConversionStats last_;
};

}  // namespace stridemap
