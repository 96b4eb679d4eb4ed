#pragma once
// The URG-04LX on a walking robot (WalkSensor): the simulator scans from the
// true pose, and the pipeline's ScanIntegrator takes the raw scan with the
// estimate: sensor model, the chosen scan filters (the estimate travels
// with the scan through their delay), and the map update.
#include <cstdint>
#include <memory>
#include <vector>

#include "stridemap/core/map_update.hpp"
#include "stridemap/experiments/walk_sensor.hpp"
#include "stridemap/pipeline/scan_integrator.hpp"
#include "stridemap/preprocess/scan_filter_chain.hpp"
#include "stridemap/sensors/urg04lx.hpp"
#include "stridemap/sim/footprint_beam_model.hpp"
#include "stridemap/sim/scene.hpp"
#include "stridemap/sim/urg_simulator.hpp"

namespace stridemap {

struct UrgWalkSensorOptions {
  /// Default: the paper's Messor mount, 0.26 m, 35 deg (Fig. 8c).
  SensorMount mount{};
  UrgParameters urg{};
  RangeCalibration calibration{};
  UrgSimOptions sim{};
  /// Footprint beam model (mixed pixels at edges); off: one ray per beam.
  bool mixed_pixels = false;
  FootprintBeamOptions footprint{};
  /// Scan filters between the sensor model and the mapper (none by default).
  std::vector<ScanFilterKind> filters{};
  ScanFilterChainOptions filter_options{};
  /// The visibility clean-up (core/visibility_clearing.hpp) after each scan.
  VisibilityOptions visibility{};
};

/// The URG's recording: each simulated scan with the true pose and time it
/// was simulated for (a replay checks them).
struct UrgWalkRecording final : WalkRecording {
  struct Scan {
    TrunkPose truth;
    double time_s = 0.0;
    UrgRawScan raw;
  };
  std::vector<Scan> scans;
};

class UrgWalkSensor final : public WalkSensor {
 public:
  /// Copies the scene. The predicted height uncertainty of last_points()
  /// is the mapper's own (its update options); `update` is not needed any
  /// more and kept so that callers compile unchanged. Throws InputError for
  /// unusable options.
  UrgWalkSensor(const Scene& scene, const UrgWalkSensorOptions& options, const UpdateOptions& update,
                std::uint64_t seed);

  std::string name() const override { return "urg"; }
  const SensorMount& mount() const override { return options_.mount; }
  double frame_period_s() const override { return options_.urg.scan_period_s; }
  ScanStats measure(const TrunkPose& truth, const TrunkPose& estimate, double time_s, TerrainMapper& mapper) override;
  ScanStats flush(TerrainMapper& mapper) override;
  bool start_recording() override;
  std::shared_ptr<const WalkRecording> recording() const override { return recording_; }
  bool replay(std::shared_ptr<const WalkRecording> recording) override;
  void set_collect_points(bool collect) override { integrator_.set_collect_points(collect); }
  const std::vector<ObservedPoint>& last_points() const override { return integrator_.last_points(); }
  const VisibilityClearing* visibility() const override { return integrator_.visibility(); }
  void floor_trace(const TrunkPose& pose, double floor_elevation_m, double max_range_m,
                   std::vector<Eigen::Vector2d>& out) const override;

  const UrgConversionStats& sensor_totals() const { return integrator_.stats().beams; }

 private:
  UrgWalkSensorOptions options_;
  UrgSimulator simulator_;
  ScanIntegrator integrator_;
  UrgRawScan raw_;
  std::vector<double> cos_beam_, sin_beam_;
  std::shared_ptr<UrgWalkRecording> recording_;
  std::shared_ptr<const UrgWalkRecording> replayed_;
  std::size_t next_replayed_ = 0;
};

/// The share of ranges to horizontal surfaces from lowest_m to highest_m
/// relative to the ground under the robot (section 4.2: -0.10 to +0.15 m,
/// what Messor climbs) that fall in [min_range_m, max_range_m] (0.2-0.9 m,
/// where the URG's errors are lowest, Fig. 6). Over `levels` evenly spaced
/// surface heights and every beam that meets the surface ahead of the
/// sensor within `corridor_half_width_m` of the robot's centre line (the
/// strip its feet use), from the nominal pose. 0 when no beam meets any of
/// the surfaces.
struct RangeIntervalOptions {
  double lowest_m = -0.10, highest_m = 0.15;
  int levels = 26;  ///< every 1 cm
  double min_range_m = 0.2, max_range_m = 0.9;
  double corridor_half_width_m = 0.30;
};
double urg_share_in_range_interval(const SensorMount& mount, const UrgParameters& urg,
                                   const RangeIntervalOptions& options = {});

}  // namespace stridemap
