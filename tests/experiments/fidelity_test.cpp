// Random scenes and the fidelity experiment's distributions.
#include <algorithm>
#include <cmath>
#include <set>
#include <string>

#include <gtest/gtest.h>

#include "stridemap/config/scene_yaml.hpp"
#include "stridemap/experiments/fidelity.hpp"

namespace stridemap {
namespace {

TEST(RandomScene, SameSeedSameTextOtherSeedOtherScene) {
  for (RandomSceneKind kind : {RandomSceneKind::boxes, RandomSceneKind::rocky, RandomSceneKind::steps}) {
    EXPECT_EQ(random_scene_yaml(kind, 7), random_scene_yaml(kind, 7));
    EXPECT_NE(random_scene_yaml(kind, 7), random_scene_yaml(kind, 8));
  }
}

// Every seed's scene loads with the scene loader (a rocky path that left the
// patch, or two boxes given one name, would be an InputError here).
TEST(RandomScene, ManySeedsLoadAndMeetTheBrief) {
  std::set<long> millimetre_remainders;
  double lowest_reflectance = 1.0, highest_reflectance = 0.0, lowest_box = 1.0, highest_box = 0.0;
  std::size_t turned = 0, square = 0;
  for (std::uint64_t seed = 0; seed < 60; ++seed) {
    for (RandomSceneKind kind : {RandomSceneKind::boxes, RandomSceneKind::steps}) {
      const Scene scene = parse_scene_yaml(random_scene_yaml(kind, seed), "seed " + std::to_string(seed));
      ASSERT_TRUE(scene.cart_rail.has_value());
      for (const BoxObject& box : scene.boxes) {
        lowest_reflectance = std::min(lowest_reflectance, box.reflectance);
        highest_reflectance = std::max(highest_reflectance, box.reflectance);
        lowest_box = std::min(lowest_box, box.height_m);
        highest_box = std::max(highest_box, box.height_m);
        (box.yaw_rad == 0.0 ? square : turned) += 1;
        millimetre_remainders.insert(std::lround(box.length_m * 1000.0) % 10);
      }
    }
    if (seed < 8) {
      const Scene rocky = parse_scene_yaml(random_scene_yaml(RandomSceneKind::rocky, seed), "rocky");
      EXPECT_TRUE(rocky.walk_path.has_value());
    }
  }
  EXPECT_LT(lowest_reflectance, 0.2);
  EXPECT_GT(highest_reflectance, 0.8);
  EXPECT_LT(lowest_box, 0.04) << "flat objects";
  EXPECT_GT(highest_box, 0.1) << "tall objects";
  EXPECT_GT(square, 10u);
  EXPECT_GT(turned, 10u);
  EXPECT_GE(millimetre_remainders.size(), 8u) << "sizes off the 10 mm grid";
}

TEST(FigureDistribution, MedianNinetiethAndWorstOnTheBadSide) {
  std::vector<double> values;
  for (int i = 1; i <= 11; ++i) values.push_back(i);
  values.push_back(std::nan(""));
  const FigureDistribution lower = distribution_of("error", values, false);
  EXPECT_EQ(lower.count, 11u);
  EXPECT_DOUBLE_EQ(lower.median, 6.0);
  EXPECT_DOUBLE_EQ(lower.p90, 10.0);
  EXPECT_DOUBLE_EQ(lower.worst, 11.0);
  const FigureDistribution higher = distribution_of("removed", values, true);
  EXPECT_DOUBLE_EQ(higher.median, 6.0);
  EXPECT_DOUBLE_EQ(higher.p90, 2.0);
  EXPECT_DOUBLE_EQ(higher.worst, 1.0);
  EXPECT_TRUE(std::isnan(distribution_of("none", {}, false).median));
}

TEST(Fidelity, OneSceneGivesEveryFigureAndIsDeterministic) {
  FidelityOptions options;
  options.scenes = 1;
  options.seed = 3;
  options.structured_light = false;
  const FidelityResult a = run_fidelity(options);
  const FidelityResult b = run_fidelity(options);
  ASSERT_EQ(a.scenes.size(), 1u);
  EXPECT_EQ(fidelity_summary_json(a, options), fidelity_summary_json(b, options));
  const FidelitySceneResult& row = a.scenes.front();
  EXPECT_EQ(row.scene_seed, 3000u);
  EXPECT_FALSE(row.urg_objects.empty());
  // The ideal sensor measures the same objects: the extents' floor.
  ASSERT_EQ(row.urg_ideal_sensor_objects.size(), row.urg_objects.size());
  for (std::size_t k = 0; k < row.urg_objects.size(); ++k) {
    EXPECT_EQ(row.urg_ideal_sensor_objects[k].name, row.urg_objects[k].name);
  }
  const auto has_figure = [&](const std::string& name) {
    return std::any_of(a.figures.begin(), a.figures.end(), [&](const FigureDistribution& d) {
      return d.figure.starts_with(name) && d.count > 0;
    });
  };
  EXPECT_TRUE(has_figure("urg_ideal_sensor_box_width_error_mm"));
  EXPECT_TRUE(has_figure("urg_ideal_sensor_box_length_error_mm"));
  EXPECT_TRUE(std::any_of(a.edges.begin(), a.edges.end(), [](const EdgeErrorSpread& e) {
    return e.sensor == "urg_ideal_sensor" && e.count > 0;
  }));
  EXPECT_NE(fidelity_summary_json(a, options).find("\"urg_ideal_sensor_objects\""), std::string::npos);
  EXPECT_GE(row.artifact_cells_unfiltered, row.artifact_cells_reference);
  EXPECT_LT(row.clean_beams_dropped_pct, 10.0);
  EXPECT_GE(a.figures.size(), 5u);
  options.scenes = 0;
  EXPECT_THROW(run_fidelity(options), InputError);
}

TEST(RandomScene, BystandersStandBesideTheLineAndLeaveItsObjectsAlone) {
  std::size_t white = 0, black = 0;
  for (std::uint64_t seed = 0; seed < 30; ++seed) {
    const Scene plain = parse_scene_yaml(random_scene_yaml(RandomSceneKind::boxes, seed), "plain");
    const Scene with = parse_scene_yaml(random_scene_yaml(RandomSceneKind::boxes, seed, true), "with");
    EXPECT_EQ(random_scene_yaml(RandomSceneKind::boxes, seed, true), random_scene_yaml(RandomSceneKind::boxes, seed, true));
    ASSERT_GE(with.boxes.size(), plain.boxes.size());
    for (std::size_t k = 0; k < plain.boxes.size(); ++k) EXPECT_EQ(with.boxes[k].name, plain.boxes[k].name);
    EXPECT_EQ(with.terrain.reflectance, plain.terrain.reflectance);
    for (std::size_t k = plain.boxes.size(); k < with.boxes.size(); ++k) {
      const BoxObject& b = with.boxes[k];
      EXPECT_TRUE(b.name.starts_with(kBystanderPrefix)) << b.name;
      EXPECT_GE(b.height_m, 0.08);
      EXPECT_GE(std::abs(b.center_y_m) - b.width_m / 2, 0.099) << b.name << " seed " << seed;
      white += b.reflectance >= 0.75;
      black += b.reflectance <= 0.2;
    }
  }
  EXPECT_GT(white, 5u);
  EXPECT_GT(black, 5u);
}

TEST(Fidelity, StructuredLightFiguresIncludeFalseDetectionsAndFloorErrors) {
  FidelityOptions options;
  options.scenes = 1;
  options.seed = 3;
  options.structured_light_rail.structured_light.pipeline = StripePipeline::geometric;
  const FidelityResult result = run_fidelity(options);
  const FidelitySceneResult& row = result.scenes.front();
  EXPECT_GE(row.structured_light_lux, 50.0);
  EXPECT_LE(row.structured_light_lux, 1000.0);
  EXPECT_EQ(row.structured_light_false_detections_pct, 0.0);  // the true stripe
  EXPECT_EQ(row.structured_light_off_surface_detections_pct, 0.0);
  EXPECT_EQ(row.structured_light_clear_artifact_cells, 0.0);
  EXPECT_GT(row.structured_light_rms_error_mm, 0.0);
  EXPECT_GE(row.structured_light_max_error_mm, row.structured_light_clear_max_error_mm);
  EXPECT_GE(row.structured_light_rms_level_mm, 0.0);
  EXPECT_LE(row.structured_light_rms_beyond_span_mm, row.structured_light_max_error_mm);
  EXPECT_NE(row.scene_yaml.find(kBystanderPrefix), std::string::npos);
  const std::string json = fidelity_summary_json(result, options);
  for (const char* key : {"structured_light_false_detections_pct", "structured_light_false_detections_off_row_pct",
                          "structured_light_false_detections_off_surface_pct",
                          "structured_light_cells_off_20mm_clear_of_objects",
                          "structured_light_max_error_clear_of_objects_mm", "structured_light_max_error_mm",
                          "structured_light_rms_error_mm", "structured_light_rms_error_level_cells_mm",
                          "structured_light_rms_beyond_span_mm", "structured_light_cells_beyond_span_20mm",
                          "urg_rms_error_level_cells_mm", "urg_rms_beyond_span_mm", "structured_light_lux",
                          "saturation_halo_dn"}) {
    EXPECT_NE(json.find(key), std::string::npos) << key;
  }
  const std::string table = fidelity_table(result);
  EXPECT_NE(table.find("structured_light_cells_off_20mm_clear_of_objects"), std::string::npos) << table;
  options.min_lux = 0.0;
  EXPECT_THROW(run_fidelity(options), InputError);
}

TEST(Fidelity, RefusesAFilteredRunWithoutFilters) {
  FidelityOptions options;
  options.scenes = 1;
  options.structured_light = false;
  options.filters.clear();
  try {
    run_fidelity(options);
    ADD_FAILURE() << "no InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("at least one scan filter"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace stridemap
