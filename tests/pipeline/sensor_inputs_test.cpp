// One test per input kind: the pipeline gives the same map as the sensor
// model and the mapper wired by hand, and it rejects data it cannot use
// with a message that names what is wrong.
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "pipeline_test_support.hpp"
#include "stridemap/core/error.hpp"
#include "stridemap/pipeline/mapping_pipeline.hpp"

namespace stridemap {
namespace {

using test::floor_scan;
using test::pose_at;

void expect_same_layers(const ElevationMap& a, const ElevationMap& b) {
  ASSERT_EQ(a.cells_per_side(), b.cells_per_side());
  const std::size_t n = static_cast<std::size_t>(a.cells_per_side()) * static_cast<std::size_t>(a.cells_per_side());
  std::size_t measured = 0;
  for (std::size_t k = 0; k < n; ++k) {
    ASSERT_EQ(a.state_data()[k], b.state_data()[k]) << "slot " << k;
    if (a.state_data()[k] != static_cast<std::uint8_t>(CellState::measured)) continue;
    ++measured;
    ASSERT_EQ(a.elevation_data()[k], b.elevation_data()[k]) << "slot " << k;
    ASSERT_EQ(a.certainty_data()[k], b.certainty_data()[k]) << "slot " << k;
  }
  EXPECT_GT(measured, 20u);
}

TEST(PipelineInputs, UrgRawScansGiveTheMapOfTheModelAndMapperByHand) {
  PipelineOptions options;
  MappingPipeline pipeline(options);
  UrgModel model(options.urg, options.calibration);
  TerrainMapper by_hand(options.mapper, options.mount);
  PlanarScan scan;
  for (int k = 0; k < 5; ++k) {
    const UrgRawScan raw = floor_scan(0.1 * k);
    const TrunkPose pose = pose_at(0.01 * k, 0.02 * k);
    const ScanOutcome out = pipeline.add(raw, pose);
    model.to_planar_scan(raw, scan);
    const ScanStats expected = by_hand.integrate(scan, pose);
    EXPECT_TRUE(out.integrated);
    EXPECT_EQ(out.stats.integrated, expected.integrated);
  }
  expect_same_layers(pipeline.mapper().map(), by_hand.map());
  EXPECT_EQ(pipeline.stats().scans, 5u);
  EXPECT_EQ(pipeline.stats().integrated, 5u);
  EXPECT_GT(pipeline.stats().beams.valid, 0u);
}

TEST(PipelineInputs, AUrgScanThatDoesNotFitTheSensorIsCountedNotIntegrated) {
  MappingPipeline pipeline(PipelineOptions{});
  UrgRawScan raw = floor_scan(0.0);
  raw.first_step = 10;  // below the sensor's first measurable step (44)
  const ScanOutcome out = pipeline.add(raw, pose_at(0.0));
  EXPECT_FALSE(out.integrated);
  EXPECT_EQ(pipeline.stats().rejected, 1u);
  EXPECT_EQ(pipeline.mapper().totals().scans, 0u);
}

TEST(PipelineInputs, StructuredLightFramesGiveTheMapOfStripeToMapPoints) {
  PipelineOptions options;
  options.sensor = SensorKind::structured_light;
  options.mount = options.structured_light.mount;
  options.mapper.grid.cell_size_m = 0.005;
  MappingPipeline pipeline(options);
  const StructuredLightModel model(options.structured_light);
  TerrainMapper by_hand(options.mapper, options.mount);
  StripeFrame frame;
  for (int u = 0; u < options.structured_light.image_width_px; u += 4) {
    frame.pixels.push_back({u + 0.5, 0.6 * options.structured_light.image_height_px + 0.01 * u});
  }
  frame.pixels.push_back({NAN, 10.0});
  std::vector<MapPoint> points;
  for (int k = 0; k < 4; ++k) {
    frame.time_s = 0.04 * k;
    const TrunkPose pose = pose_at(0.004 * k);
    const ScanOutcome out = pipeline.add(frame, pose);
    stripe_to_map_points(model, frame.pixels, pose, by_hand.motion_to(pose), options.mapper.update, points);
    const ScanStats expected = by_hand.integrate_points(points, pose, frame.time_s);
    EXPECT_EQ(out.stats.integrated, expected.integrated);
    EXPECT_EQ(out.stats.beams, expected.beams);
  }
  expect_same_layers(pipeline.mapper().map(), by_hand.map());
  EXPECT_EQ(pipeline.stats().stripe.not_finite, 4u);
  EXPECT_EQ(pipeline.stats().stripe.pixels, 4 * frame.pixels.size());
}

TEST(PipelineInputs, GenericPointsLandWhereTheyAreWithTheirSigmaAsTheBound) {
  PipelineOptions options;
  options.sensor = SensorKind::points;
  options.mount.pitch_rad = 0.0;
  options.mount.height_m = 0.5;
  options.mapper.update.max_pitch_error_rad = 0.0;
  options.mapper.update.max_roll_error_rad = 0.0;
  options.mapper.update.max_mount_pitch_error_rad = 0.0;
  MappingPipeline pipeline(options);
  // A point 0.3 m ahead, 0.4 m below the sensor: 0.1 m above the ground.
  PointFrame frame;
  frame.time_s = 1.0;
  frame.points_m = {{0.3, 0.0, -0.4}, {NAN, 0.0, 0.0}};
  frame.height_sigma_m = {0.01, 0.01};
  ScanOutcome out = pipeline.add(frame, pose_at(0.0));
  EXPECT_EQ(out.stats.integrated, 1u);
  EXPECT_EQ(pipeline.stats().points.not_finite, 1u);
  const ElevationMap& map = pipeline.mapper().map();
  const CellIndex cell = map.cell_of(0.3, 0.0);
  EXPECT_NEAR(map.elevation(cell), 0.1, 1e-6);

  // 2 cm higher is within 3 sigma (plausible); 5 cm higher is not.
  frame.time_s = 2.0;
  frame.points_m = {{0.3, 0.0, -0.38}};
  frame.height_sigma_m = {0.01};
  out = pipeline.add(frame, pose_at(0.0));
  EXPECT_EQ(out.stats.plausible, 1u);
  frame.time_s = 3.0;
  frame.points_m = {{0.3, 0.0, -0.33}};
  out = pipeline.add(frame, pose_at(0.0));
  EXPECT_EQ(out.stats.implausible, 1u);

  frame.height_sigma_m.clear();
  EXPECT_THROW(
      {
        try {
          pipeline.add(frame, pose_at(0.0));
        } catch (const InputError& e) {
          EXPECT_NE(std::string(e.what()).find("1 points but 0 sigmas"), std::string::npos) << e.what();
          throw;
        }
      },
      InputError);
}

TEST(PipelineInputs, OptionsThatCannotWorkAreRefusedBeforeAnyScan) {
  PipelineOptions options;
  options.sensor = SensorKind::structured_light;
  options.filters = {ScanFilterKind::range_clustering};
  try {
    MappingPipeline pipeline(options);
    FAIL() << "filters on a stripe sensor were accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("structured-light sensor takes none"), std::string::npos) << e.what();
  }
  options = {};
  options.map_filter.filter = MapFilter::fill;
  options.map_filter.fill.window_radius_cells = 0;
  EXPECT_THROW(MappingPipeline{options}, InputError);
  options = {};
  options.points.sigma_scale = -1.0;
  EXPECT_THROW(MappingPipeline{options}, InputError);
}

TEST(PipelineInputs, DataOfAnotherSensorIsAnError) {
  MappingPipeline pipeline(PipelineOptions{});
  PointFrame frame;
  try {
    pipeline.add(frame, pose_at(0.0));
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("configured for the urg sensor, given points data"), std::string::npos)
        << e.what();
  }
}

TEST(PipelineNames, SensorKindsAndMapFiltersRoundTrip) {
  for (SensorKind k : {SensorKind::urg, SensorKind::structured_light, SensorKind::points, SensorKind::custom}) {
    EXPECT_EQ(parse_sensor_kind(sensor_kind_name(k)), k);
  }
  for (MapFilter f : {MapFilter::none, MapFilter::fill, MapFilter::cas}) {
    EXPECT_EQ(parse_map_filter(map_filter_name(f)), f);
  }
  EXPECT_THROW(parse_sensor_kind("sonar"), InputError);
  EXPECT_THROW(parse_map_filter("blur"), InputError);
}

}  // namespace
}  // namespace stridemap
