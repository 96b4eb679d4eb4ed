// Foothold layers (core/foothold.hpp) on analytic terrain against their
// closed forms, and the incremental update against a from-scratch one.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>
#include <limits>
#include <numbers>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "stridemap/core/error.hpp"
#include "stridemap/core/foothold.hpp"
#include "stridemap/core/terrain_mapper.hpp"

namespace stridemap {
namespace {

constexpr double kDegPerRad = 180.0 / std::numbers::pi;
constexpr double kCell = 0.01;

// A 60 x 60 map of 1 cm cells whose every cell is measured at f(centre).
ElevationMap terrain(const std::function<double(double, double)>& f, float certainty = 9.0f) {
  ElevationMap map(GridOptions{60, kCell});
  for (int i = 0; i < 60; ++i) {
    for (int j = 0; j < 60; ++j) {
      const CellIndex c = map.cell_at_local(i, j);
      const Eigen::Vector2d p = map.cell_center(c);
      const std::size_t s = map.slot(c);
      map.elevation_data()[s] = static_cast<float>(f(p.x(), p.y()));
      map.certainty_data()[s] = certainty;
      map.state_data()[s] = static_cast<std::uint8_t>(CellState::measured);
    }
  }
  return map;
}

float at(const ElevationMap& map, LayerId<float> id, CellIndex c) { return map.data(id)[map.slot(c)]; }

// Cells far enough from the window's border that their footprint and edge
// search see only terrain.
std::vector<CellIndex> interior(const ElevationMap& map, int margin) {
  std::vector<CellIndex> cells;
  for (int i = margin; i < map.cells_per_side() - margin; ++i) {
    for (int j = margin; j < map.cells_per_side() - margin; ++j) cells.push_back(map.cell_at_local(i, j));
  }
  return cells;
}

double expected_score(const FootholdOptions& o, double slope_deg, double step_m, double rough_m, double edge_m,
                      double certainty) {
  const auto down = [](double v, double limit) { return std::clamp(1.0 - v / limit, 0.0, 1.0); };
  return down(slope_deg, o.max_slope_deg) * down(step_m, o.max_step_m) * down(rough_m, o.max_roughness_m) *
         std::min(1.0, edge_m / o.edge_clearance_m) * std::min(1.0, certainty / o.full_certainty);
}

TEST(Foothold, TiltedPlaneHasItsSlopeNoRoughnessAndTheFootprintsRise) {
  // z = a x + b y: gradient 0.25, 0.2 -> slope atan(0.32) = 17.74 deg.
  const double a = 0.25, b = 0.2;
  ElevationMap map = terrain([&](double x, double y) { return a * x + b * y + 0.3; });
  const FootholdOptions options;  // 2 cm foot: footprint offsets up to 2 cells
  FootholdLayers foothold(map, options);
  foothold.recompute_all(map);
  const double slope = std::atan(std::hypot(a, b)) * kDegPerRad;
  // Max minus min of a x + b y over the footprint's cell centres: the disc
  // of radius 2 cells holds (+-2, 0), (0, +-2) and (+-1, +-1); the largest
  // of a dx + b dy is max(2a, 2b, a + b) cells.
  const double rise = 2.0 * kCell * std::max({2 * a, 2 * b, a + b});
  for (const CellIndex& c : interior(map, 3)) {
    EXPECT_NEAR(at(map, foothold.slope(), c), slope, 2e-3);
    EXPECT_LT(at(map, foothold.roughness(), c), 2e-5);
    EXPECT_NEAR(at(map, foothold.step_height(), c), rise, 1e-5);
    EXPECT_FLOAT_EQ(at(map, foothold.edge_distance(), c), static_cast<float>(options.edge_search_radius_m));
    EXPECT_NEAR(at(map, foothold.score(), c), expected_score(options, slope, rise, 0.0, 0.1, 9.0), 1e-4);
  }
}

TEST(Foothold, StepMarksItsEdgeAndDistancesGrowAwayFromIt) {
  // A 10 cm step where x crosses 0.05 m: cells x index >= 5 are high.
  const double height = 0.10;
  ElevationMap map = terrain([&](double x, double) { return x >= 0.05 ? height : 0.0; });
  const FootholdOptions options;
  FootholdLayers foothold(map, options);
  foothold.recompute_all(map);
  for (const CellIndex& c : interior(map, 3)) {
    // The footprint reaches 2 cells either way, so cells 3..6 straddle it.
    const bool straddles = c.x >= 3 && c.x <= 6;
    EXPECT_NEAR(at(map, foothold.step_height(), c), straddles ? height : 0.0, 1e-6) << c.x;
    double edge = 0.0;
    if (c.x < 3) edge = static_cast<double>(3 - c.x) * kCell;
    if (c.x > 6) edge = static_cast<double>(c.x - 6) * kCell;
    edge = std::min(edge, options.edge_search_radius_m);
    EXPECT_NEAR(at(map, foothold.edge_distance(), c), edge, 1e-6) << c.x;
    if (!straddles) {
      EXPECT_NEAR(at(map, foothold.slope(), c), 0.0, 1e-4);
      EXPECT_NEAR(at(map, foothold.roughness(), c), 0.0, 1e-6);
      EXPECT_NEAR(at(map, foothold.score(), c), expected_score(options, 0.0, 0.0, 0.0, edge, 9.0), 1e-5) << c.x;
    } else {
      EXPECT_EQ(at(map, foothold.score(), c), 0.0f);
    }
  }
}

TEST(Foothold, RampHasItsSlopeInsideAndIsFlatBeyond) {
  // Flat, then rising at 1:2 (26.57 deg) from x = 0 to 0.1 m, then flat.
  const auto z = [](double x, double) { return 0.5 * std::clamp(x, 0.0, 0.1); };
  ElevationMap map = terrain(z);
  FootholdOptions options;
  options.max_step_m = 0.5;  // no edges: the ramp alone
  FootholdLayers foothold(map, options);
  foothold.recompute_all(map);
  const double ramp_slope = std::atan(0.5) * kDegPerRad;
  for (const CellIndex& c : interior(map, 3)) {
    // Footprint wholly on the ramp: x indices 2..7 (centres 0.025..0.075 m
    // with 2 cells either side inside [0, 0.1]).
    if (c.x >= 2 && c.x <= 7) {
      EXPECT_NEAR(at(map, foothold.slope(), c), ramp_slope, 2e-3) << c.x;
      EXPECT_LT(at(map, foothold.roughness(), c), 2e-5);
      EXPECT_NEAR(at(map, foothold.step_height(), c), 0.5 * 4 * kCell, 1e-5);
    } else if (c.x <= -3 || c.x >= 12) {
      EXPECT_NEAR(at(map, foothold.slope(), c), 0.0, 1e-4) << c.x;
      EXPECT_NEAR(at(map, foothold.step_height(), c), 0.0, 1e-6);
    } else {
      // At a kink the plane fit leaves a residual and the slope lies between.
      EXPECT_GT(at(map, foothold.roughness(), c), 1e-4) << c.x;
      EXPECT_GT(at(map, foothold.slope(), c), 0.0);
      EXPECT_LT(at(map, foothold.slope(), c), ramp_slope);
    }
  }
}

TEST(Foothold, SphereSlopeIsTheTangentAngleAndTheApexIsRoundish) {
  const double radius = 0.5;
  const auto z = [&](double x, double y) { return std::sqrt(radius * radius - x * x - y * y) - radius; };
  ElevationMap map = terrain(z);
  FootholdLayers foothold(map, FootholdOptions{});
  foothold.recompute_all(map);
  for (const CellIndex& c : interior(map, 3)) {
    const Eigen::Vector2d p = map.cell_center(c);
    if (p.norm() > 0.3) continue;  // beyond 37 deg the cubic terms grow past the tolerance
    // The tangent plane at distance d from the apex is inclined asin(d / R);
    // a symmetric fit cancels the even (curvature) terms, leaving O(r^2/R^2).
    EXPECT_NEAR(at(map, foothold.slope(), c), std::asin(p.norm() / radius) * kDegPerRad, 0.05) << p.transpose();
  }
  // At a cell next to the apex (centre 5 mm off each axis) the footprint's
  // step is the sphere's drop between the nearest and farthest centres.
  const CellIndex apex{0, 0};
  double lo = 1e9, hi = -1e9;
  for (int dx = -2; dx <= 2; ++dx) {
    for (int dy = -2; dy <= 2; ++dy) {
      if (dx * dx + dy * dy > 4) continue;
      const double v = z((dx + 0.5) * kCell, (dy + 0.5) * kCell);
      lo = std::min(lo, v);
      hi = std::max(hi, v);
    }
  }
  EXPECT_NEAR(at(map, foothold.step_height(), apex), hi - lo, 2e-6);
  // Near the apex the sphere is the paraboloid -(x^2 + y^2) / 2R; on the
  // symmetric footprint the plane takes its mean and linear part, leaving
  // the RMS of -(dx^2 + dy^2) s^2 / 2R about its mean.
  double sum = 0.0, sum_sq = 0.0, cells = 0.0;
  for (int dx = -2; dx <= 2; ++dx) {
    for (int dy = -2; dy <= 2; ++dy) {
      if (dx * dx + dy * dy > 4) continue;
      const double q = -(dx * dx + dy * dy) * kCell * kCell / (2.0 * radius);
      sum += q;
      sum_sq += q * q;
      cells += 1.0;
    }
  }
  const double rms = std::sqrt(sum_sq / cells - (sum / cells) * (sum / cells));
  EXPECT_NEAR(at(map, foothold.roughness(), apex), rms, 3e-6);
}

TEST(Foothold, UnknownCellsAndThinFootprintsAreUnknownNotUnsafe) {
  ElevationMap map = terrain([](double, double) { return 0.0; });
  // A hole of one unknown cell, and a cell whose footprint is mostly unknown.
  const CellIndex hole{0, 0};
  map.state_data()[map.slot(hole)] = 0;
  map.elevation_data()[map.slot(hole)] = std::numeric_limits<float>::quiet_NaN();
  for (int dx = -2; dx <= 2; ++dx) {
    for (int dy = -2; dy <= 2; ++dy) {
      if ((dx == 0 && dy == 0) || dx + dy < 0) continue;
      const CellIndex c{10 + dx, 10 + dy};
      map.state_data()[map.slot(c)] = 0;
      map.elevation_data()[map.slot(c)] = std::numeric_limits<float>::quiet_NaN();
    }
  }
  FootholdLayers foothold(map, FootholdOptions{});
  foothold.recompute_all(map);
  for (LayerId<float> id : {foothold.slope(), foothold.roughness(), foothold.step_height(), foothold.edge_distance(),
                            foothold.score()}) {
    EXPECT_TRUE(std::isnan(at(map, id, hole)));
  }
  EXPECT_TRUE(std::isnan(at(map, foothold.score(), CellIndex{10, 10})));
  EXPECT_TRUE(std::isnan(at(map, foothold.slope(), CellIndex{10, 10})));
  // A known neighbour of the hole still has a value, the flat ground a full score.
  EXPECT_FLOAT_EQ(at(map, foothold.score(), CellIndex{-5, -5}), 1.0f);
}

TEST(Foothold, LowCertaintyLowersTheScore) {
  ElevationMap map = terrain([](double, double) { return 0.0; }, 3.0f);
  FootholdLayers foothold(map, FootholdOptions{});
  foothold.recompute_all(map);
  EXPECT_NEAR(at(map, foothold.score(), CellIndex{0, 0}), 3.0 / 9.0, 1e-6);
}

TEST(Foothold, BadOptionsNameTheField) {
  ElevationMap map(GridOptions{20, kCell});
  const auto message = [&](FootholdOptions o) {
    try {
      FootholdLayers f(map, o);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  FootholdOptions o;
  o.foot_radius_m = -0.01;
  EXPECT_NE(message(o).find("foot_radius_m"), std::string::npos);
  o = {};
  o.max_slope_deg = std::numeric_limits<double>::quiet_NaN();
  EXPECT_NE(message(o).find("max_slope_deg"), std::string::npos);
  o = {};
  o.safe_score = 1.5;
  EXPECT_NE(message(o).find("safe_score"), std::string::npos);
  o = {};
  o.max_step_m = 0.0;
  EXPECT_NE(message(o).find("max_step_m"), std::string::npos);
}

TEST(Foothold, AttachesToAMapThatAlreadyHasTheLayersAndRefusesAWrongType) {
  ElevationMap map(GridOptions{20, kCell});
  FootholdLayers first(map, FootholdOptions{});
  const std::size_t layers = map.layer_count();
  FootholdLayers second(map, FootholdOptions{});
  EXPECT_EQ(map.layer_count(), layers);
  ElevationMap other(GridOptions{20, kCell});
  other.add_layer({"slope_deg", LayerType::u8, 0.0, "", "not a slope"});
  EXPECT_THROW(FootholdLayers(other, FootholdOptions{}), InputError);
}

void expect_same_layers(const ElevationMap& a, const ElevationMap& b, const FootholdLayers& f, int step) {
  const std::size_t cells = static_cast<std::size_t>(a.cells_per_side()) * static_cast<std::size_t>(a.cells_per_side());
  ASSERT_EQ(a.min_cell(), b.min_cell());
  for (LayerId<float> id : {f.slope(), f.roughness(), f.step_height(), f.edge_distance(), f.score()}) {
    // Bit for bit, NaN included: the same code on the same cells.
    ASSERT_EQ(std::memcmp(a.data(id), b.data(id), cells * sizeof(float)), 0)
        << a.layer_spec(id.index).name << " after update " << step;
  }
}

// How a walk hands its changes to the layers.
enum class Feed { box_every_scan, rows_every_scan, rows_read_now_and_then };

// `cells`: the window's side; past 64 a row's marks take several words.
void random_walk_equals_recomputation(Feed feed, int cells = 50) {
  MapperOptions options;
  options.grid = GridOptions{cells, kCell};
  options.reject_stale_scans = false;
  TerrainMapper mapper(options, SensorMount{});
  FootholdOptions foothold_options;
  foothold_options.max_step_m = 0.03;  // plenty of edges on this terrain
  FootholdLayers foothold(mapper.map(), foothold_options);
  foothold.recompute_all(mapper.map());
  std::mt19937 rng(18);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::uniform_int_distribution<int> gap(1, 9);
  const auto ground = [](double x, double y) {
    return 0.04 * std::sin(9 * x) * std::cos(7 * y) + (std::fmod(std::abs(x + 3 * y), 0.3) < 0.1 ? 0.06 : 0.0);
  };
  double x = 0.0, y = 0.0;
  std::vector<MapPoint> points;
  int next_read = gap(rng), checks = 0;
  for (int step = 0; step < 120; ++step) {
    // Wander so that the window moves in both directions, now and then by
    // a lot, once by more than the window, and back and forth in a row.
    x += step % 17 == 16 ? 0.4 * unit(rng) : 0.03 * unit(rng);
    y += step % 23 == 22 ? 0.4 * unit(rng) : 0.03 * unit(rng);
    if (step == 61) x += 0.7;
    if (step % 31 == 30) y -= 0.06;
    if (step % 31 == 0 && step > 0) y += 0.06;
    TrunkPose pose;
    pose.x_m = x;
    pose.y_m = y;
    points.clear();
    // A scan-like line across the window, sometimes diagonal, sometimes a blob.
    const double angle = 3.0 * unit(rng), ahead = 0.1 + 0.1 * unit(rng);
    for (int k = 0; k < 60; ++k) {
      const double t = 0.3 * (k / 59.0 - 0.5);
      const double px = x + ahead * std::cos(angle) - t * std::sin(angle) + (step % 5 == 0 ? 0.05 * unit(rng) : 0.0);
      const double py = y + ahead * std::sin(angle) + t * std::cos(angle);
      points.push_back({px, py, ground(px, py) + 0.002 * unit(rng), 0.02});
    }
    mapper.integrate_points(points, pose);
    bool read = true;
    switch (feed) {
      case Feed::box_every_scan: foothold.update(mapper.map(), mapper.take_changed_cells()); break;
      case Feed::rows_every_scan:
        foothold.update(mapper.map(), mapper.changed_rows());
        mapper.clear_changed_cells();
        break;
      case Feed::rows_read_now_and_then:
        foothold.note(mapper.map(), mapper.changed_rows());
        mapper.clear_changed_cells();
        read = --next_read == 0;
        if (read) {
          next_read = gap(rng);
          foothold.refresh(mapper.map());
        }
        break;
    }
    if (read) {  // every refresh, against a recomputation
      ASSERT_TRUE(foothold.current());
      ElevationMap scratch = mapper.map();
      FootholdLayers fresh(scratch, foothold_options);
      fresh.recompute_all(scratch);
      expect_same_layers(mapper.map(), scratch, foothold, step);
      ++checks;
    }
  }
  EXPECT_GE(checks, 12);
}

TEST(Foothold, IncrementalUpdatesEqualARecomputationAfterRandomScansAndWindowMoves) {
  random_walk_equals_recomputation(Feed::box_every_scan);
}

TEST(Foothold, PerRowUpdatesEqualARecomputationAfterRandomScansAndWindowMoves) {
  random_walk_equals_recomputation(Feed::rows_every_scan);
}

TEST(Foothold, LazyRefreshAfterSeveralScansEqualsARecomputation) {
  random_walk_equals_recomputation(Feed::rows_read_now_and_then);
}

TEST(Foothold, LazyRefreshOnAWindowOfSeveralMarkWordsEqualsARecomputation) {
  random_walk_equals_recomputation(Feed::rows_read_now_and_then, 150);
}

TEST(Foothold, ADiagonalScanLineRedoesOnlyTheCellsAroundItByRowsOrByBox) {
  MapperOptions options;
  options.grid = GridOptions{100, kCell};
  TerrainMapper mapper(options, SensorMount{}), twin(options, SensorMount{});
  FootholdLayers by_box(mapper.map(), FootholdOptions{}), by_rows(twin.map(), FootholdOptions{});
  by_box.recompute_all(mapper.map());
  by_rows.recompute_all(twin.map());
  std::vector<MapPoint> points;
  for (int k = 0; k < 200; ++k) {
    const double t = -0.4 + 0.8 * k / 199.0;  // the window's diagonal
    points.push_back({t, t, 0.01 + 0.02 * std::sin(30.0 * t), 0.02});
  }
  mapper.integrate_points(points, TrunkPose{});
  twin.integrate_points(points, TrunkPose{});
  by_box.update(mapper.map(), mapper.changed_cells());
  by_rows.update(twin.map(), twin.changed_rows());
  ElevationMap scratch = twin.map();
  FootholdLayers fresh(scratch, FootholdOptions{});
  fresh.recompute_all(scratch);
  expect_same_layers(twin.map(), scratch, by_rows, 0);
  expect_same_layers(mapper.map(), scratch, by_box, 0);
  // The box is half the window, but only cells whose elevation changed
  // count: the line's 100 cells grown by the footprint, either way.
  EXPECT_GT(by_rows.last_geometry_cells(), 100u);
  EXPECT_LT(by_rows.last_geometry_cells(), 100u * 13u);
  EXPECT_EQ(by_box.last_geometry_cells(), by_rows.last_geometry_cells());
  EXPECT_EQ(by_box.last_score_cells(), by_rows.last_score_cells());
  EXPECT_TRUE(by_rows.current());
  by_rows.refresh(twin.map());  // nothing noted since: nothing redone
  EXPECT_EQ(by_rows.last_geometry_cells(), 0u);
}

TEST(Foothold, ReadingsThatOnlyRaiseTheCertaintyRedoScoresButNoPlaneFits) {
  MapperOptions options;
  options.grid = GridOptions{60, kCell};
  options.reject_stale_scans = false;
  TerrainMapper mapper(options, SensorMount{});
  const FootholdOptions foothold_options;  // full certainty 9: three readings at a = 3
  FootholdLayers foothold(mapper.map(), foothold_options);
  foothold.recompute_all(mapper.map());
  std::vector<MapPoint> points;
  for (int k = 0; k < 40; ++k) {
    const double t = -0.2 + 0.4 * k / 39.0;
    points.push_back({0.1 + 0.3 * t, t, 0.02 * std::sin(20.0 * t), 0.02});
  }
  std::vector<std::size_t> geometry, scores;
  for (int scan = 0; scan < 5; ++scan) {
    // The same readings again: plausible, none above the elevation, so only
    // the certainty rises (3, 6, 9, then capped in the score at 9).
    mapper.integrate_points(points, TrunkPose{});
    foothold.update(mapper.map(), mapper.changed_rows());
    mapper.clear_changed_cells();
    geometry.push_back(foothold.last_geometry_cells());
    scores.push_back(foothold.last_score_cells());
    ElevationMap scratch = mapper.map();
    FootholdLayers fresh(scratch, foothold_options);
    fresh.recompute_all(scratch);
    expect_same_layers(mapper.map(), scratch, foothold, scan);
  }
  EXPECT_GT(geometry[0], 40u);
  EXPECT_EQ(geometry[1], 0u);
  EXPECT_EQ(geometry[2], 0u);
  EXPECT_EQ(geometry[3], 0u);
  // Certainty 3 -> 6 -> 9 changes the score of the line's cells; beyond the
  // full certainty nothing changes.
  EXPECT_GT(scores[1], 10u);
  EXPECT_GT(scores[2], 10u);
  EXPECT_EQ(scores[3], 0u);
  EXPECT_EQ(scores[4], 0u);
}

TEST(Foothold, TheMappersChangedBoxCoversTheCellsItWrote) {
  MapperOptions options;
  options.grid = GridOptions{80, kCell};
  SensorMount mount;
  TerrainMapper mapper(options, mount);
  PlanarScan scan;
  scan.resize(40);
  for (std::size_t i = 0; i < 40; ++i) {
    const double t = -0.6 + 1.2 * static_cast<double>(i) / 39.0;
    scan.angle_rad[i] = t;
    scan.range_m[i] = mount.height_m / (std::cos(t) * std::sin(mount.pitch_rad));
    scan.range_error_m[i] = 0.01;
  }
  TrunkPose pose;
  pose.yaw_rad = 0.7;  // a diagonal line through the wrapped window
  pose.x_m = 0.137;
  ASSERT_GT(mapper.integrate(scan, pose).integrated, 0u);
  const CellBox box = mapper.take_changed_cells();
  ASSERT_FALSE(box.empty());
  EXPECT_TRUE(mapper.changed_cells().empty());
  std::size_t known = 0;
  CellBox tight;
  for (int i = 0; i < 80; ++i) {
    for (int j = 0; j < 80; ++j) {
      const CellIndex c = mapper.map().cell_at_local(i, j);
      if (mapper.map().state(c) == CellState::unknown) continue;
      ++known;
      tight.add(c);
    }
  }
  EXPECT_GT(known, 5u);
  // Exactly the written cells' bounds: every side touches a written cell.
  EXPECT_EQ(box.min, tight.min);
  EXPECT_EQ(box.max, tight.max);
  EXPECT_TRUE(mapper.changed_rows().empty());  // cleared with the box
}

TEST(Foothold, TheMappersChangedRowsAreTheWrittenCellsRowByRow) {
  MapperOptions options;
  options.grid = GridOptions{80, kCell};
  SensorMount mount;
  TerrainMapper mapper(options, mount);
  PlanarScan scan;
  scan.resize(40);
  for (std::size_t i = 0; i < 40; ++i) {
    const double t = -0.6 + 1.2 * static_cast<double>(i) / 39.0;
    scan.angle_rad[i] = t;
    scan.range_m[i] = mount.height_m / (std::cos(t) * std::sin(mount.pitch_rad));
    scan.range_error_m[i] = 0.01;
  }
  TrunkPose pose;
  pose.yaw_rad = 0.7;  // a diagonal line through the wrapped window
  pose.x_m = 0.137;
  ASSERT_GT(mapper.integrate(scan, pose).integrated, 0u);
  // The per-point path adds its cells too.
  const Eigen::Vector2d far = mapper.map().cell_center(mapper.map().cell_at_local(3, 70));
  mapper.integrate_points(std::vector<MapPoint>{{far.x(), far.y(), 0.0, 0.02}}, pose);
  const ChangedRows& rows = mapper.changed_rows();
  std::size_t rows_seen = 0;
  for (int i = 0; i < 80; ++i) {
    CellBox tight;
    for (int j = 0; j < 80; ++j) {
      const CellIndex c = mapper.map().cell_at_local(i, j);
      if (mapper.map().state(c) != CellState::unknown) tight.add(c);
    }
    std::int64_t lo = 0, hi = 0;
    const CellIndex first = mapper.map().cell_at_local(i, 0);
    ASSERT_EQ(rows.span(first.x, lo, hi), !tight.empty()) << "row " << i;
    if (tight.empty()) continue;
    ++rows_seen;
    EXPECT_EQ(lo, tight.min.y) << "row " << i;
    EXPECT_EQ(hi, tight.max.y) << "row " << i;
  }
  EXPECT_GT(rows_seen, 5u);
}

}  // namespace
}  // namespace stridemap
