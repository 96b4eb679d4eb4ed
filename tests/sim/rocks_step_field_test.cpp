#include <cmath>

#include <gtest/gtest.h>

#include "stridemap/core/error.hpp"
#include "stridemap/sim/height_field.hpp"
#include "stridemap/sim/step_field.hpp"

namespace stridemap {
namespace {

ProceduralTerrainOptions ground() {
  ProceduralTerrainOptions o;
  o.min_x_m = 0, o.min_y_m = -1, o.max_x_m = 2, o.max_y_m = 1;
  o.resolution_m = 0.01;
  o.amplitude_m = 0.02;
  o.wavelength_m = 0.5;
  return o;
}

TEST(Rocks, RiseAboveTheGroundWithinTheirClassAndArea) {
  const HeightField bare = make_procedural_height_field(ground(), 5);
  ProceduralTerrainOptions o = ground();
  o.rocks.classes = {{3, 0.10, 0.15, 0.06, 0.09}, {10, 0.02, 0.04, 0.01, 0.02}};
  o.rocks.area = std::array<double, 4>{1.0, -0.5, 1.8, 0.5};
  const HeightField rocky = make_procedural_height_field(o, 5);
  ASSERT_EQ(rocky.samples.size(), bare.samples.size());
  double highest_rise = 0.0;
  for (std::size_t k = 0; k < bare.samples.size(); ++k) {
    const double rise = rocky.samples[k] - bare.samples[k];
    ASSERT_GE(rise, 0.0);  // the terrain takes the higher of ground and rock
    highest_rise = std::max(highest_rise, rise);
    const double x = rocky.min_x_m + static_cast<double>(k % static_cast<std::size_t>(rocky.nx)) * rocky.resolution_m;
    if (rise > 0.0) EXPECT_GE(x, 1.0 - 0.15 - 1e-9) << "a rock outside its area";
  }
  // The ground around a rock varies by up to 4 cm, so a rock rises by up
  // to its height plus that variation above the ground at other points.
  EXPECT_GT(highest_rise, 0.05);
  EXPECT_LT(highest_rise, 0.09 + 0.04);
  // Adding rocks leaves the ground where there are none.
  EXPECT_EQ(rocky.samples.front(), bare.samples.front());
}

TEST(Rocks, BadClassesAreReported) {
  ProceduralTerrainOptions o = ground();
  o.rocks.classes = {{2, 0.2, 0.1, 0.05, 0.06}};
  auto problem = o.first_problem();
  ASSERT_TRUE(problem);
  EXPECT_EQ(problem->field_path, "rocks[0].max_radius_m");
  o.rocks.classes = {{2, 0.1, 0.2, -0.05, 0.06}};
  EXPECT_EQ(o.first_problem()->field_path, "rocks[0].min_height_m");
  o.rocks.classes = {{-1, 0.1, 0.2, 0.05, 0.06}};
  EXPECT_EQ(o.first_problem()->field_path, "rocks[0].count");
  o.rocks.classes = {};
  o.rocks.area = std::array<double, 4>{1.0, 0.0, 0.5, 1.0};
  EXPECT_EQ(o.first_problem()->field_path, "rocks_area.max_x_m");
  EXPECT_THROW(make_procedural_height_field(o, 1), InputError);
}

TEST(StepField, BlocksAreDeterministicAndWithinTheirHeights) {
  StepFieldOptions o;
  const Scene a = make_step_field(o, 3), b = make_step_field(o, 3), c = make_step_field(o, 4);
  ASSERT_EQ(a.boxes.size(), b.boxes.size());
  ASSERT_FALSE(a.boxes.empty());
  const double places = (o.max_x_m - o.min_x_m) / o.block_size_m * (o.max_y_m - o.min_y_m) / o.block_size_m;
  EXPECT_NEAR(static_cast<double>(a.boxes.size()) / places, 1.0 - o.empty_fraction, 0.1);
  bool differs = a.boxes.size() != c.boxes.size();
  for (std::size_t k = 0; k < a.boxes.size(); ++k) {
    EXPECT_EQ(a.boxes[k].height_m, b.boxes[k].height_m);
    EXPECT_GE(a.boxes[k].height_m, o.min_height_m);
    EXPECT_LE(a.boxes[k].height_m, o.max_height_m);
    if (k < c.boxes.size() && c.boxes[k].height_m != a.boxes[k].height_m) differs = true;
  }
  EXPECT_TRUE(differs);
  EXPECT_LE(a.terrain.min_x_m, o.min_x_m - o.margin_m);
  o.empty_fraction = 1.0;
  EXPECT_THROW(make_step_field(o, 1), InputError);
  o = StepFieldOptions{};
  o.block_size_m = 0.0;
  EXPECT_THROW(make_step_field(o, 1), InputError);
}

}  // namespace
}  // namespace stridemap
