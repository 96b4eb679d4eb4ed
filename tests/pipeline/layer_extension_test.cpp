// The extension story for map layers, told from outside src/: a new layer
// is one declaration (here in the map options) plus the code that updates
// it (here a PipelineObserver); the map resets it as the window moves,
// copies it with the map and exports it by name like the built-in layers.
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "stridemap/core/error.hpp"
#include "stridemap/core/exported_map.hpp"
#include "stridemap/pipeline/mapping_pipeline.hpp"

namespace stridemap {
namespace {

LayerSpec hit_count_layer() {
  LayerSpec spec;
  spec.name = "hit_count";
  spec.type = LayerType::u16;
  spec.reset_value = 0.0;
  spec.description = "points the pipeline integrated in the cell";
  return spec;
}

// Counts the points of every integrated scan per cell. The handle is looked
// up once; the per-point work is a slot look-up and an increment.
class HitCounter final : public PipelineObserver {
 public:
  explicit HitCounter(MappingPipeline& pipeline)
      : pipeline_(pipeline), hits_(pipeline.mapper().map().layer<std::uint16_t>("hit_count")) {}
  void on_scan(const ScanReport&) override {
    ElevationMap& map = pipeline_.mapper().map();
    std::uint16_t* hits = map.data(hits_);
    for (const IntegratedPoint& p : pipeline_.integrator().last_points()) {
      std::size_t slot = 0;
      if (map.slot_at(p.map_m.x(), p.map_m.y(), slot) && hits[slot] < 0xFFFF) ++hits[slot];
    }
  }

 private:
  MappingPipeline& pipeline_;
  LayerId<std::uint16_t> hits_;
};

PipelineOptions point_options() {
  PipelineOptions options;
  options.sensor = SensorKind::points;
  options.mount.pitch_rad = 0.0;
  options.mount.height_m = 0.0;  // sensor frame = trunk frame = map frame at the origin
  options.mapper.follow_robot = false;
  options.mapper.grid.cells_per_side = 40;
  options.mapper.grid.cell_size_m = 0.05;
  options.mapper.grid.extra_layers = {hit_count_layer()};
  return options;
}

PointFrame frame(double time_s, const std::vector<Eigen::Vector3d>& points) {
  PointFrame f;
  f.time_s = time_s;
  f.points_m = points;
  f.height_sigma_m.assign(points.size(), 0.01);
  return f;
}

TEST(LayerExtension, ALayerDeclaredOutsideTheLibraryIsUpdatedExportedAndReset) {
  MappingPipeline pipeline(point_options());
  HitCounter counter(pipeline);
  pipeline.integrator().set_collect_points(true);
  pipeline.integrator().add_observer(counter);

  TrunkPose pose;
  pose.reference_elevation_m = 0.0;
  const Eigen::Vector3d a(0.12, 0.13, 0.02), b(-0.31, 0.22, 0.05);
  pipeline.add(frame(0.0, {a, a + Eigen::Vector3d(0.01, 0.0, 0.0), a, b}), pose);
  pipeline.add(frame(0.1, {a, a, Eigen::Vector3d(10.0, 0.0, 0.0)}), pose);  // the last one is off the map

  const ElevationMap& map = pipeline.mapper().map();
  const CellIndex cell_a = map.cell_of(a.x(), a.y()), cell_b = map.cell_of(b.x(), b.y());
  const auto hits = map.layer<std::uint16_t>("hit_count");
  EXPECT_EQ(map.data(hits)[map.slot(cell_a)], 5);
  EXPECT_EQ(map.data(hits)[map.slot(cell_b)], 1);

  // Selected by name, in window order, beside a built-in layer.
  const std::vector<std::string> names{"hit_count", "elevation"};
  const ExportedMap exported = export_map(map, names);
  ASSERT_EQ(exported.layers.size(), 2u);
  const CountMatrix& counts = exported.layer("hit_count").u16;
  const auto local = [&](CellIndex c) { return std::pair{c.x - map.min_cell().x, c.y - map.min_cell().y}; };
  EXPECT_EQ(counts(local(cell_a).first, local(cell_a).second), 5);
  EXPECT_EQ(counts(local(cell_b).first, local(cell_b).second), 1);
  EXPECT_EQ(counts.cast<int>().sum(), 6);
  EXPECT_FLOAT_EQ(exported.elevation_m()(local(cell_b).first, local(cell_b).second), 0.05f);
  // Declared exported (the default), so in the default export too.
  EXPECT_NE(export_map(map).find("hit_count"), nullptr);
  EXPECT_EQ(export_map(map).find("mean_count"), nullptr);

  // The filtered copy a planner gets carries it.
  const ElevationMap filtered = pipeline.filtered_map();
  EXPECT_EQ(filtered.data(filtered.layer<std::uint16_t>("hit_count"))[filtered.slot(cell_a)], 5);

  // Cells the window leaves get the declared reset value, like every layer.
  ElevationMap moved = map;
  moved.move_to(100.0, 100.0);
  const std::uint16_t* moved_hits = moved.data(hits);
  for (std::size_t s = 0; s < 40u * 40u; ++s) ASSERT_EQ(moved_hits[s], 0) << s;
}

TEST(LayerExtension, UnknownNamesAndWrongTypesAreClearErrors) {
  ElevationMap map(GridOptions{8, 0.1, {hit_count_layer()}});
  try {
    map.layer<std::uint16_t>("hits");
    FAIL() << "no error";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("'hits'"), std::string::npos) << what;
    EXPECT_NE(what.find("elevation, certainty"), std::string::npos) << what;
    EXPECT_NE(what.find("hit_count"), std::string::npos) << what;
  }
  EXPECT_THROW(map.layer<float>("hit_count"), InputError);
  EXPECT_THROW(export_map(map, std::vector<std::string>{"elevation", "roughness"}), InputError);
  EXPECT_THROW(map.add_layer(hit_count_layer()), InputError);  // the name is taken
  LayerSpec bad = hit_count_layer();
  bad.name = "Hit Count";
  EXPECT_THROW(map.add_layer(bad), InputError);
  bad.name = "flag";
  bad.type = LayerType::u8;
  bad.reset_value = 300.0;
  EXPECT_THROW(map.add_layer(bad), InputError);
  // A layer added after construction starts at its reset value.
  LayerSpec roughness;
  roughness.name = "roughness";
  roughness.unit = "m";
  roughness.reset_value = std::nan("");
  const auto id = LayerId<float>{map.add_layer(roughness)};
  EXPECT_TRUE(std::isnan(map.data(id)[0]));
  EXPECT_EQ(map.layer<float>("roughness").index, id.index);
}

}  // namespace
}  // namespace stridemap
