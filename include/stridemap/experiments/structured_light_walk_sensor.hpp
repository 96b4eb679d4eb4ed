#pragma once
// The camera + laser-stripe sensor on a walking robot (WalkSensor): each
// frame is simulated from the true pose (sim/structured_light_simulator.hpp
// and, on the image path, rendered and searched by the stripe detector),
// and the pipeline's ScanIntegrator turns the stripe into points by eq. (1),
// (5) and (8) with the estimated pose and integrates them.
#include <cstdint>
#include <optional>
#include <vector>

#include "stridemap/core/map_update.hpp"
#include "stridemap/experiments/cart_rail.hpp"
#include "stridemap/experiments/walk_sensor.hpp"
#include "stridemap/pipeline/scan_integrator.hpp"
#include "stridemap/render/png_image.hpp"
#include "stridemap/sim/structured_light_image.hpp"
#include "stridemap/sim/structured_light_simulator.hpp"
#include "stridemap/vision/stripe_detector.hpp"

namespace stridemap {

struct StructuredLightWalkSensorOptions {
  /// Ragno's sensor (section 3.3); its mount is the sensor's mount.
  StructuredLightParameters parameters{};
  /// geometric by default for walks: the simulator's true stripe with
  /// row_noise_sigma_px of noise (a sub-pixel detector's spread); image
  /// renders every frame and runs the detector (slower, includes its misses).
  StripePipeline pipeline = StripePipeline::geometric;
  /// Geometry options; the row noise defaults to 0.3 px here.
  StructuredLightSimOptions geometry = [] {
    StructuredLightSimOptions o;
    o.row_noise_sigma_px = 0.3;
    return o;
  }();
  StripeImageOptions image{};
  io::StripeDetectorOptions detector{};
  double min_confidence = 0.0;
  /// Time between camera frames [s]. 25 Hz: 4 mm of travel per frame at the
  /// gait's 0.1 m/s, under the 5 mm cells the paper maps structured light
  /// into.
  double frame_period_s = 0.04;
};

class StructuredLightWalkSensor final : public WalkSensor {
 public:
  /// Copies the scene; `update` bounds the predicted height uncertainty of
  /// last_points() (the mapper's). Throws InputError for unusable options
  /// or a mount that cannot see the ground.
  StructuredLightWalkSensor(const Scene& scene, const StructuredLightWalkSensorOptions& options,
                            const UpdateOptions& update, std::uint64_t seed);

  std::string name() const override { return "structured-light"; }
  const SensorMount& mount() const override { return options_.parameters.mount; }
  double frame_period_s() const override { return options_.frame_period_s; }
  ScanStats measure(const TrunkPose& truth, const TrunkPose& estimate, double time_s, TerrainMapper& mapper) override;
  ScanStats flush(TerrainMapper& mapper) override { return integrator_.flush(mapper).stats; }
  void set_collect_points(bool collect) override { integrator_.set_collect_points(collect); }
  const std::vector<ObservedPoint>& last_points() const override { return integrator_.last_points(); }
  void floor_trace(const TrunkPose& pose, double floor_elevation_m, double max_range_m,
                   std::vector<Eigen::Vector2d>& out) const override;

  const StripeConversionStats& conversion_totals() const { return integrator_.stats().stripe; }

 private:
  StructuredLightWalkSensorOptions options_;
  UpdateOptions update_;
  StructuredLightModel model_;
  std::optional<StructuredLightImageRenderer> renderer_;
  std::optional<StructuredLightSimulator> simulator_;
  StructuredLightSimulator floor_geometry_;  ///< sensor poses for floor_trace (scene unused)
  io::StripeDetector detector_;
  io::RgbImage image_;
  io::StripeDetection detection_;
  StructuredLightFrameTruth truth_;
  std::vector<StripePixel> pixels_;
  std::vector<Eigen::Vector3d> column_rays_;  ///< emitter ray per column, camera frame
  ScanIntegrator integrator_;
};

}  // namespace stridemap
