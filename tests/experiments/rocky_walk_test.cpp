#include "stridemap/experiments/rocky_walk.hpp"

#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "stridemap/config/scene_yaml.hpp"
#include "stridemap/core/error.hpp"
#include "stridemap/experiments/rocky_walk_report.hpp"
#include "stridemap/experiments/urg_walk_sensor.hpp"
#include "test_paths.hpp"

namespace stridemap {
namespace {

Scene mockup() { return load_scene_yaml(std::string(STRIDEMAP_SOURCE_DIR) + "/scenes/rocky_mockup.yaml"); }

WalkSensorFactory urg() {
  return [](const Scene& scene, const UpdateOptions& update) -> std::unique_ptr<WalkSensor> {
    return std::make_unique<UrgWalkSensor>(scene, UrgWalkSensorOptions{}, update, 1);
  };
}

TEST(RockyWalk, TheMockUpIsMappedAndTheErrorGrowsWithThePoseError) {
  const Scene scene = mockup();
  RockyWalkOptions options;
  options.pose_error_scales = {0.0, 1.0, 4.0};
  const RockyWalkResult r = run_rocky_walk(scene, *scene.walk_path, urg(), options);
  EXPECT_EQ(r.sensor, "urg");
  const WalkResult& w = r.main;
  EXPECT_GT(w.scans, 400u);
  EXPECT_GT(w.scans_with_yaw_change, w.scans / 2);  // the camera's yaw noise and the turns
  EXPECT_GT(w.mosaic_score.coverage, 0.9);
  EXPECT_GT(w.unknown_swept_cells, 0u);  // shadows behind the rocks stay unknown
  ASSERT_EQ(r.sweep.size(), 9u);         // 3 levels x (h_ref truth, map, map-mean)
  // h_ref from the truth: the map's error grows with the IMU, camera and
  // leg errors, from the rail-like floor at zero error.
  EXPECT_EQ(r.sweep[0].reference, ReferenceElevationSource::truth);
  EXPECT_LT(r.sweep[0].score.rms_error_m, 0.006);
  EXPECT_LT(r.sweep[0].score.rms_error_m, r.sweep[1].score.rms_error_m);
  EXPECT_LT(r.sweep[1].score.rms_error_m, r.sweep[2].score.rms_error_m);
  EXPECT_LT(r.sweep[0].score.artifact_cells, r.sweep[2].score.artifact_cells);
  // h_ref from the map drifts up: the max-height rule's bias is fed back
  // through every step (docs/experiments.md); worse than the truth rows.
  for (int k = 0; k < 3; ++k) {
    EXPECT_EQ(r.sweep[3 + k].reference, ReferenceElevationSource::map);
    EXPECT_GT(r.sweep[3 + k].pose.mean_sensor_height_m, 0.0);
    EXPECT_GT(r.sweep[3 + k].score.rms_error_m, r.sweep[k].score.rms_error_m);
  }
  // From the cells' means the noise no longer feeds back: with no pose error
  // h_ref stays within a few millimetres, and at every level it drifts less.
  for (int k = 0; k < 3; ++k) {
    EXPECT_EQ(r.sweep[6 + k].reference, ReferenceElevationSource::map_mean);
    EXPECT_LT(r.sweep[6 + k].pose.sensor_height_m, r.sweep[3 + k].pose.sensor_height_m);
    EXPECT_LT(r.sweep[6 + k].score.rms_error_m, r.sweep[3 + k].score.rms_error_m);
  }
  EXPECT_LT(r.sweep[6].pose.sensor_height_m, 0.005);
  // The main walk is the x1 map row, reused.
  EXPECT_EQ(r.sweep[4].score.rms_error_m, w.mosaic_score.rms_error_m);

  const nlohmann::json summary = nlohmann::json::parse(rocky_walk_summary_json(r, options, {"scene", "path"}));
  EXPECT_EQ(summary["source"], "simulation");
  EXPECT_EQ(summary["pose_error_sweep"].size(), 9u);
  for (const char* key : {"rms_error_m", "max_error_m", "artifact_cells", "coverage", "unknown_swept_cells"}) {
    EXPECT_TRUE(summary["map"].contains(key)) << key;
  }
  EXPECT_NE(rocky_walk_table(r).find("unknown cells behind obstacles"), std::string::npos);
}

TEST(RockyWalk, BadSweepLevelsAreRejectedBeforeAnyWalk) {
  const Scene scene = mockup();
  RockyWalkOptions options;
  options.pose_error_scales = {1.0, -0.5};
  int sensors_made = 0;
  const WalkSensorFactory counting = [&](const Scene& s, const UpdateOptions& u) -> std::unique_ptr<WalkSensor> {
    ++sensors_made;
    return urg()(s, u);
  };
  EXPECT_THROW(run_rocky_walk(scene, *scene.walk_path, counting, options), InputError);
  EXPECT_EQ(sensors_made, 0);
}

}  // namespace
}  // namespace stridemap
