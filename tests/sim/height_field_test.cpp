#include "stridemap/sim/height_field.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <numbers>
#include <random>

#include <gtest/gtest.h>

#include "stridemap/core/error.hpp"

namespace stridemap {
namespace {

// A field of nx x ny samples at 10 mm from (0, 0), heights from a function.
HeightField field_from(int nx, int ny, const std::function<double(double, double)>& height, double base = 0.0) {
  HeightField field;
  field.resolution_m = 0.01;
  field.nx = nx;
  field.ny = ny;
  field.min_x_m = 0.0;
  field.min_y_m = 0.0;
  field.max_x_m = (nx - 1) * field.resolution_m;
  field.max_y_m = (ny - 1) * field.resolution_m;
  field.base_elevation_m = base;
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) field.samples.push_back(static_cast<float>(height(i * 0.01, j * 0.01)));
  }
  return field;
}

Eigen::Vector3d unit(double x, double y, double z) { return Eigen::Vector3d(x, y, z).normalized(); }

TEST(HeightFieldCast, FlatFieldAtKnownAngle) {
  HeightField flat;
  flat.base_elevation_m = 0.1;
  const double angle = 35.0 * std::numbers::pi / 180.0;  // below horizontal
  const auto hit = flat.cast_ray({0.0, 0.0, 0.36}, {std::cos(angle), 0.0, -std::sin(angle)}, 5.0);
  ASSERT_TRUE(hit);
  EXPECT_NEAR(hit->range_m, 0.26 / std::sin(angle), 1e-12);
  EXPECT_NEAR(hit->point_m.z(), 0.1, 1e-12);
  EXPECT_TRUE(hit->normal.isApprox(Eigen::Vector3d::UnitZ()));
  EXPECT_EQ(hit->object_index, -1);
  EXPECT_FALSE(flat.cast_ray({0.0, 0.0, 0.36}, {std::cos(angle), 0.0, -std::sin(angle)}, 0.4));
  EXPECT_FALSE(flat.cast_ray({0.0, 0.0, 0.36}, unit(1.0, 0.0, 0.1), 100.0));
  EXPECT_FALSE(flat.cast_ray({0.0, 0.0, 0.36}, Eigen::Vector3d::UnitX(), 100.0));
}

TEST(HeightFieldCast, OriginBelowSurfaceHitsAtZero) {
  HeightField flat;
  const auto hit = flat.cast_ray({0.0, 0.0, -0.01}, Eigen::Vector3d::UnitX(), 1.0);
  ASSERT_TRUE(hit);
  EXPECT_EQ(hit->range_m, 0.0);
}

TEST(HeightFieldCast, InclinedPlaneIsExact) {
  const double slope = 0.3;
  const HeightField field = field_from(101, 51, [&](double x, double) { return slope * x; });
  const Eigen::Vector3d origin(0.1, 0.2, 0.5);
  const Eigen::Vector3d dir = unit(1.0, 0.2, -0.8);
  const auto hit = field.cast_ray(origin, dir, 2.0);
  ASSERT_TRUE(hit);
  // origin.z + t dz = slope (origin.x + t dx)
  const double t = (slope * origin.x() - origin.z()) / (dir.z() - slope * dir.x());
  // Samples are floats: exact up to their rounding (about 1e-8 m here).
  EXPECT_NEAR(hit->range_m, t, 1e-7);
  EXPECT_TRUE(hit->normal.isApprox(unit(-slope, 0.0, 1.0), 1e-6));
  EXPECT_NEAR(field.height_at(hit->point_m.x(), hit->point_m.y()), hit->point_m.z(), 1e-12);
}

TEST(HeightFieldCast, DoesNotTunnelThroughASingleSpikeAtGrazingAngle) {
  // One sample 0.1 m high, all others 0: a pyramid 20 mm wide at the base.
  const HeightField field = field_from(41, 41, [](double x, double y) {
    return std::abs(x - 0.2) < 1e-9 && std::abs(y - 0.2) < 1e-9 ? 0.1 : 0.0;
  });
  // Horizontal ray along the spike's grid line at 95 mm: along y = 0.2 the
  // surface is a tent 0.1 (1 - |x - 0.2| / 0.01), met at x = 0.2 - 0.0005.
  auto hit = field.cast_ray({0.0, 0.2, 0.095}, Eigen::Vector3d::UnitX(), 1.0);
  ASSERT_TRUE(hit);
  EXPECT_NEAR(hit->point_m.x(), 0.2 - 0.0005, 1e-9);
  // Off the grid line, 3 mm over: h = 0.1 * u * 0.7 in the cell before the
  // spike, met at u = 0.065 / 0.07.
  hit = field.cast_ray({0.0, 0.203, 0.065}, Eigen::Vector3d::UnitX(), 1.0);
  ASSERT_TRUE(hit);
  EXPECT_NEAR(hit->point_m.x(), 0.19 + 0.01 * 0.065 / 0.07, 1e-9);
  // Just above the tip: nothing.
  EXPECT_FALSE(field.cast_ray({0.0, 0.2, 0.1001}, Eigen::Vector3d::UnitX(), 1.0));
  // A horizontal diagonal ray along y = x + 0.5 mm: in the cell above the
  // spike's row the surface along it is 0.1 u (1.95 - u), u in [0.95, 1],
  // highest (95.0625 mm) at u = 0.975, between two grid lines. A ray 30 um
  // below that top must hit; 10 um above it must not.
  const Eigen::Vector3d diagonal = unit(1.0, 1.0, 0.0);
  hit = field.cast_ray({0.0, 0.0005, 0.09503}, diagonal, 1.0);
  ASSERT_TRUE(hit);
  EXPECT_NEAR(field.height_at(hit->point_m.x(), hit->point_m.y()), hit->point_m.z(), 1e-9);
  EXPECT_NEAR(hit->point_m.x(), 0.19975, 0.0002);
  EXPECT_FALSE(field.cast_ray({0.0, 0.0005, 0.09507}, diagonal, 1.0));
}

TEST(HeightFieldCast, SaddleHitLiesOnTheSurfaceAndNothingEarlier) {
  // h = c (x - 0.25)(y - 0.25) is bilinear, so every cell is a saddle piece
  // and the ray meets a quadratic.
  const HeightField field = field_from(51, 51, [](double x, double y) { return 4.0 * (x - 0.25) * (y - 0.25); });
  const Eigen::Vector3d origin(0.02, 0.45, 0.2);
  const Eigen::Vector3d dir = unit(1.0, -0.9, -0.35);
  const auto hit = field.cast_ray(origin, dir, 2.0);
  ASSERT_TRUE(hit);
  EXPECT_NEAR(field.height_at(hit->point_m.x(), hit->point_m.y()), hit->point_m.z(), 1e-9);
  for (double t = 0.0; t < hit->range_m - 1e-6; t += 1e-5) {
    const Eigen::Vector3d p = origin + t * dir;
    ASSERT_GT(p.z(), field.height_at(p.x(), p.y())) << "crossing before the reported hit at t = " << t;
  }
}

TEST(HeightFieldCast, MatchesFineMarchOnProceduralTerrain) {
  ProceduralTerrainOptions options;
  options.min_x_m = 0.0;
  options.min_y_m = 0.0;
  options.max_x_m = 1.0;
  options.max_y_m = 1.0;
  options.resolution_m = 0.02;
  options.amplitude_m = 0.05;
  options.wavelength_m = 0.2;
  const HeightField field = make_procedural_height_field(options, 11);
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> position(0.1, 0.9), slope(-0.4, -0.01), heading(0.0, 2.0 * std::numbers::pi);
  int hits = 0;
  for (int ray = 0; ray < 150; ++ray) {
    const double yaw = heading(rng);
    const Eigen::Vector3d origin(position(rng), position(rng), 0.06);
    const Eigen::Vector3d dir = unit(std::cos(yaw), std::sin(yaw), slope(rng));
    const auto hit = field.cast_ray(origin, dir, 1.5, field.max_sample_height_m());
    EXPECT_EQ(hit.has_value(), field.cast_ray(origin, dir, 1.5).has_value());
    const double end = hit ? hit->range_m - 1e-6 : 1.5;
    for (double t = 0.0; t < end; t += 2e-5) {
      const Eigen::Vector3d p = origin + t * dir;
      ASSERT_GT(p.z(), field.height_at(p.x(), p.y())) << "ray " << ray << " crosses at t = " << t;
    }
    if (!hit) continue;
    ++hits;
    if (hit->normal.z() == 0.0) {
      // The step down from the flat outside (0) to lower terrain at the
      // extent's border: a wall, on the border, below the outside.
      const Eigen::Vector3d p = hit->point_m;
      EXPECT_NEAR(std::min({p.x(), 1.0 - p.x(), p.y(), 1.0 - p.y()}), 0.0, 1e-12);
      EXPECT_LT(p.z(), 0.0);
      EXPECT_GE(p.z(), field.height_at(p.x(), p.y()));
    } else {
      EXPECT_NEAR(field.height_at(hit->point_m.x(), hit->point_m.y()), hit->point_m.z(), 1e-9);
      EXPECT_GT(hit->normal.z(), 0.0);
    }
  }
  EXPECT_GT(hits, 100);
}

TEST(HeightFieldCast, StepAtTheExtentIsAWall) {
  // A raised plateau at 0.05 m inside [0, 0.4] x [0, 0.4], base 0 outside.
  const HeightField field = field_from(41, 41, [](double, double) { return 0.05; });
  auto hit = field.cast_ray({-0.5, 0.2, 0.03}, Eigen::Vector3d::UnitX(), 2.0);
  ASSERT_TRUE(hit);
  EXPECT_NEAR(hit->range_m, 0.5, 1e-12);
  EXPECT_TRUE(hit->normal.isApprox(-Eigen::Vector3d::UnitX()));
  // Over the plateau's far edge (z = 0.06 at x = 0.4) and down onto the
  // flat outside at x = 0.7.
  hit = field.cast_ray({0.1, 0.2, 0.12}, unit(1.0, 0.0, -0.2), 2.0);
  ASSERT_TRUE(hit);
  EXPECT_NEAR(hit->range_m, 0.6 * std::sqrt(1.04), 1e-12);
  EXPECT_TRUE(hit->normal.isApprox(Eigen::Vector3d::UnitZ()));
  // Out of a pit: the wall of the higher outside faces back into the pit.
  const HeightField pit = field_from(41, 41, [](double, double) { return -0.05; });
  hit = pit.cast_ray({0.1, 0.2, -0.01}, Eigen::Vector3d::UnitX(), 2.0);
  ASSERT_TRUE(hit);
  EXPECT_NEAR(hit->range_m, 0.3, 1e-12);
  EXPECT_TRUE(hit->normal.isApprox(-Eigen::Vector3d::UnitX()));
  hit = pit.cast_ray({0.1, 0.2, -0.01}, -Eigen::Vector3d::UnitY(), 2.0);
  ASSERT_TRUE(hit);
  EXPECT_NEAR(hit->range_m, 0.2, 1e-12);
  EXPECT_TRUE(hit->normal.isApprox(Eigen::Vector3d::UnitY()));
}

TEST(HeightFieldMaxInRect, ExactOverCellsAndBoundaries) {
  const HeightField spike = field_from(41, 41, [](double x, double y) {
    return std::abs(x - 0.2) < 1e-9 && std::abs(y - 0.2) < 1e-9 ? 0.1 : 0.0;
  });
  EXPECT_NEAR(spike.max_height_in_rect(0.15, 0.15, 0.25, 0.25), 0.1, 1e-7);
  // Inside the cell before the spike, not reaching it: the maximum is where
  // the rectangle's edge x = 0.1975 crosses the grid line y = 0.2.
  EXPECT_NEAR(spike.max_height_in_rect(0.195, 0.199, 0.1975, 0.201), 0.1 * 0.75, 1e-7);
  // No grid line crossed at all: a corner of the rectangle.
  EXPECT_NEAR(spike.max_height_in_rect(0.192, 0.203, 0.194, 0.205), 0.1 * 0.4 * 0.7, 1e-7);
  EXPECT_NEAR(spike.max_height_in_rect(0.0, 0.0, 0.1, 0.1), 0.0, 1e-12);

  const HeightField plane = field_from(41, 21, [](double x, double y) { return 0.1 * x - 0.05 * y; }, -0.2);
  EXPECT_NEAR(plane.max_height_in_rect(0.1, 0.05, 0.2, 0.1), 0.1 * 0.2 - 0.05 * 0.05, 1e-7);
  // Leaving the extent adds the flat outside (base -0.2, lower here).
  EXPECT_NEAR(plane.max_height_in_rect(0.35, 0.05, 0.6, 0.1), 0.1 * 0.4 - 0.05 * 0.05, 1e-7);
  EXPECT_NEAR(plane.max_height_in_rect(0.5, 0.5, 0.6, 0.6), -0.2, 1e-12);
  // Swapped corners mean the same rectangle.
  EXPECT_NEAR(plane.max_height_in_rect(0.2, 0.1, 0.1, 0.05), 0.1 * 0.2 - 0.05 * 0.05, 1e-7);
}

TEST(HeightFieldMaxInRect, NeverBelowAFineSampling) {
  ProceduralTerrainOptions options;
  options.min_x_m = 0.0;
  options.min_y_m = 0.0;
  options.max_x_m = 0.5;
  options.max_y_m = 0.5;
  options.resolution_m = 0.01;
  const HeightField field = make_procedural_height_field(options, 5);
  std::mt19937_64 rng(8);
  std::uniform_real_distribution<double> corner(0.0, 0.45), size(0.001, 0.05);
  for (int k = 0; k < 50; ++k) {
    const double x0 = corner(rng), y0 = corner(rng), x1 = x0 + size(rng), y1 = y0 + size(rng);
    const double exact = field.max_height_in_rect(x0, y0, x1, y1);
    double sampled = -1.0;
    for (int a = 0; a <= 60; ++a) {
      for (int b = 0; b <= 60; ++b) {
        sampled = std::max(sampled, field.height_at(x0 + (x1 - x0) * a / 60.0, y0 + (y1 - y0) * b / 60.0));
      }
    }
    EXPECT_GE(exact, sampled - 1e-9);
    EXPECT_LE(exact, sampled + 2e-4);  // the sampling is 1/60 of the rectangle
  }
}

TEST(ProceduralTerrain, DeterministicBoundedAndConsistent) {
  ProceduralTerrainOptions options;
  options.min_x_m = -0.5;
  options.max_x_m = 0.503;  // not a whole number of samples: rounded up
  options.amplitude_m = 0.04;
  options.base_elevation_m = 0.1;
  const HeightField a = make_procedural_height_field(options, 42);
  const HeightField b = make_procedural_height_field(options, 42);
  const HeightField c = make_procedural_height_field(options, 43);
  EXPECT_EQ(a.samples, b.samples);
  EXPECT_NE(a.samples, c.samples);
  EXPECT_EQ(a.nx, 102);
  EXPECT_NEAR(a.max_x_m, 0.51, 1e-12);
  EXPECT_EQ(a.samples.size(), static_cast<std::size_t>(a.nx) * static_cast<std::size_t>(a.ny));
  double low = 1.0, high = -1.0;
  for (float h : a.samples) low = std::min(low, double{h}), high = std::max(high, double{h});
  EXPECT_GE(low, 0.1 - 0.04 - 1e-6);
  EXPECT_LE(high, 0.1 + 0.04 + 1e-6);
  EXPECT_GT(high - low, 0.02);  // it is not flat
}

TEST(ProceduralTerrain, RejectsUnusableOptions) {
  ProceduralTerrainOptions options;
  options.resolution_m = 0.0;
  EXPECT_THROW(make_procedural_height_field(options, 1), InputError);
  options.resolution_m = 1e-5;  // 4e5 x 2e5 samples
  try {
    make_procedural_height_field(options, 1);
    FAIL() << "expected InputError";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("resolution_m: gives"), std::string::npos) << error.what();
  }
  options = {};
  options.max_x_m = options.min_x_m;
  try {
    make_procedural_height_field(options, 1);
    FAIL() << "expected InputError";
  } catch (const InputError& error) {
    EXPECT_STREQ(error.what(), "extent.max_x_m: expected a number greater than min_x_m = -1, got -1");
  }
}

}  // namespace
}  // namespace stridemap
