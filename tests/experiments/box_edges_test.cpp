// Sub-cell box edges: the top-point layers leave the
// heights alone, the edge fit recovers edges off the grid, and the
// measurement needs nothing of the truth but which object is which.
#include "stridemap/experiments/box_edges.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <cstring>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <optional>

#include <gtest/gtest.h>

#include "stridemap/config/scene_yaml.hpp"
#include "stridemap/core/sensor_transform.hpp"
#include "stridemap/experiments/cart_rail.hpp"
#include "stridemap/pipeline/top_point_observer.hpp"
#include "stridemap/sim/cart_rail.hpp"
#include "stridemap/sim/footprint_beam_model.hpp"

namespace stridemap {
namespace {

// The height the cart rail's URG scanned from, as its edge fits take it
// (ObjectMeasureOptions::sensor_height_m).
double scanner_height_m(const CartRailResult& result, const CartRailOptions& options) {
  return sensor_origin_in_map(cart_rail_poses(result.rail).front(), options.mount).z();
}

// The scan plane's pitch as the cart rail gives it (a level rail, no roll).
double scanner_pitch_rad(const CartRailResult& result, const CartRailOptions& options) {
  return options.mount.pitch_rad + cart_rail_poses(result.rail).front().pitch_rad;
}

// Boxes whose sides are no whole number of 10 mm cells, one square to the
// rail and one turned, on the rail's line (simulated URG, Messor mount).
std::string off_grid_scene(double yaw_rad) {
  return "terrain: {kind: flat, extent: {min_x_m: -0.5, min_y_m: -1.0, max_x_m: 2.5, max_y_m: 1.0}, "
         "base_elevation_m: 0.0, reflectance: 0.5}\n"
         "boxes:\n"
         "  - {name: a, center_x_m: 0.7137, center_y_m: -0.0421, length_m: 0.092, width_m: 0.137, height_m: 0.08, "
         "yaw_rad: 0.0, reflectance: 0.6}\n"
         "  - {name: b, center_x_m: 1.0561, center_y_m: 0.0234, length_m: 0.148, width_m: 0.092, height_m: 0.06, "
         "yaw_rad: " + std::to_string(yaw_rad) + ", reflectance: 0.5}\n"
         "cart_rail: {start_x_m: 0.0, end_x_m: 0.9, y_m: 0.0, step_m: 0.01}\n";
}

const ObjectMeasurement& named(const std::vector<ObjectMeasurement>& objects, const std::string& name) {
  for (const ObjectMeasurement& m : objects) {
    if (m.name == name) return m;
  }
  throw std::runtime_error("no object " + name);
}

// Readings inside a turned rectangle, denser near its edges (as edge cells
// hold them), plus a few far outside one side.
TEST(BoxEdges, FitRecoversATurnedRectangleAndTrimsOutliers) {
  const double length = 0.137, width = 0.092, yaw = 0.35;
  const Eigen::Rotation2Dd turn(yaw);
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<Eigen::Vector2d> readings;
  for (int k = 0; k < 400; ++k) {
    // Along each side, within 3 mm inside the edge.
    const int side = k % 4;
    const double along = unit(rng) - 0.5, in = 0.003 * unit(rng);
    Eigen::Vector2d local;
    if (side < 2) local = {(side == 0 ? -1 : 1) * (length / 2 - in), along * width};
    else local = {along * length, (side == 2 ? -1 : 1) * (width / 2 - in)};
    readings.push_back(turn * local);
  }
  std::vector<Eigen::Vector2d> with_outliers = readings;
  for (int k = 0; k < 12; ++k) with_outliers.push_back(turn * Eigen::Vector2d(length / 2 + 0.012, 0.02 * (k - 6) / 6.0));
  const BoxFrame frame{yaw + 0.02, -length / 2 - 0.004, length / 2 + 0.004, -width / 2 - 0.004, width / 2 + 0.004};
  BoxEdgeOptions options;
  options.edge_quantile = 1.0;  // noise-free readings: the edge is the outermost
  const BoxEdgeFit clean = fit_box_edges(readings, frame, 0.01, true, options);
  ASSERT_TRUE(clean.ok);
  EXPECT_NEAR(clean.length_m, length, 0.0005);
  EXPECT_NEAR(clean.width_m, width, 0.0005);
  EXPECT_NEAR(clean.yaw_rad, yaw, 0.005);
  const BoxEdgeFit trimmed = fit_box_edges(with_outliers, frame, 0.01, true, options);
  const BoxEdgeFit untrimmed = fit_box_edges(with_outliers, frame, 0.01, false, options);
  ASSERT_TRUE(trimmed.ok && untrimmed.ok);
  EXPECT_NEAR(trimmed.length_m, length, 0.0005);
  EXPECT_GT(untrimmed.length_m, length + 0.008);  // the outliers' side moved out
}

// The face the sensor looks at: range noise moves its readings along the
// beams, so the near face's edge cells hold readings up to a few
// millimetres in front of it as well as on the top behind it (here evenly
// within 4 mm either side of the edge). Its outer envelope is past the
// edge; given the view heading, that side's edge is its readings' middle.
TEST(BoxEdges, TheFaceTheSensorSawTakesItsReadingsMiddle) {
  const double length = 0.118, width = 0.097, yaw = 0.3;
  const Eigen::Rotation2Dd turn(yaw);
  std::vector<Eigen::Vector2d> readings;
  for (int k = 0; k < 400; ++k) {
    const int side = k % 4;
    const double along = (k / 4) / 100.0 - 0.495, spread = ((k / 4) % 10) / 9.0;
    Eigen::Vector2d local;
    if (side == 0) local = {-length / 2 + 0.004 * (2.0 * spread - 1.0), 0.8 * along * width};  // the near face
    else if (side == 1) local = {length / 2 - 0.003 * spread, 0.8 * along * width};
    else local = {0.8 * along * length, (side == 2 ? -1 : 1) * (width / 2 - 0.003 * spread)};
    readings.push_back(turn * local);
  }
  const BoxFrame frame{yaw, -length / 2 - 0.004, length / 2 + 0.004, -width / 2 - 0.004, width / 2 + 0.004};
  BoxEdgeOptions unknown_view;
  unknown_view.facing_edge_quantile = 0.5;
  BoxEdgeOptions seen = unknown_view;
  seen.view_heading_rad = 0.0;  // looking along +x: the u-min side faces the sensor
  const BoxEdgeFit blind = fit_box_edges(readings, frame, 0.01, false, unknown_view);
  const BoxEdgeFit aware = fit_box_edges(readings, frame, 0.01, false, seen);
  ASSERT_TRUE(blind.ok && aware.ok);
  EXPECT_EQ(aware.facing, (std::array<bool, 4>{true, false, false, false}));
  EXPECT_EQ(blind.facing, (std::array<bool, 4>{false, false, false, false}));
  EXPECT_GT(blind.length_m, length + 0.0025);  // the outer envelope: in front of the face
  EXPECT_NEAR(aware.length_m, length, 0.001);
  EXPECT_EQ(aware.width_m, blind.width_m);  // the sides along the view are not faces it saw
  // Looking the other way, the other u side is the face (and the fit
  // moves that side in instead).
  seen.view_heading_rad = std::numbers::pi;
  EXPECT_EQ(fit_box_edges(readings, frame, 0.01, false, seen).facing, (std::array<bool, 4>{false, true, false, false}));
}

// Boxes square to a 10 mm grid with their sides along the view (+x), as
// the cart rail scans them: one stripe per cell row, beams 1.8 mm apart
// across it, and each border cell keeping one beam's reading from the part
// of its stripe the top covers (eq. (10)'s highest, which range noise picks
// at random). The readings spread evenly over that part, the same share of
// a cell on every row, so a quantile of them falls short of the edge by a
// share of it: over many boxes the 0.9 quantile reads the widths short by
// millimetres, the stripe chords' estimate by less than half a beam spacing.
TEST(BoxEdges, SidesSquareToTheGridReachTheEdgeFromTheirStripes) {
  constexpr double s = 0.01, spacing = 0.0018;
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const auto cell_centre = [&](double w) { return (std::floor(w / s) + 0.5) * s; };
  std::vector<double> quantile_errors, stripe_errors;
  for (int box = 0; box < 200; ++box) {
    const double x0 = 0.2 + s * unit(rng), x1 = x0 + 0.1 + 0.05 * unit(rng);
    const double y0 = -0.05 - s * unit(rng), y1 = 0.04 + s * unit(rng);
    const double phase = spacing * unit(rng);  // where the beams fall across the rail
    std::vector<Eigen::Vector2d> readings, cells;
    const auto keep = [&](const Eigen::Vector2d& p) {
      readings.push_back(p);
      cells.emplace_back(cell_centre(p.x()), cell_centre(p.y()));
    };
    // A side's reading in a row: any beam on the covered part of the
    // outermost cell that holds one (a sliver no beam meets is floor).
    const auto side_reading = [&](double x, double edge, double outward) {
      for (double face = cell_centre(edge) + outward * s / 2;; face -= outward * s) {
        const double inner = std::min(face, face - outward * s), outer = std::max(face, face - outward * s);
        const double lo = std::max(inner, std::min(y0, y1)), hi = std::min(outer, std::max(y0, y1));
        std::vector<double> beams;
        for (double y = phase + spacing * std::ceil((lo - phase) / spacing); y <= hi; y += spacing) beams.push_back(y);
        if (beams.empty()) continue;
        keep({x, beams[static_cast<std::size_t>(unit(rng) * static_cast<double>(beams.size()))]});
        return;
      }
    };
    for (double x = cell_centre(x0) + s; x < x1 - s; x += s) {
      const double stripe = x + s * (unit(rng) - 0.5);
      side_reading(stripe, y0, -1.0);
      side_reading(stripe, y1, 1.0);
    }
    // The near and far sides: a millimetre or two inside their edges.
    for (double y = cell_centre(y0) + s; y < y1 - s; y += s) {
      keep({x0 + 0.002 * unit(rng), y});
      keep({x1 - 0.002 * unit(rng), y});
    }
    const BoxFrame frame{0.0, cell_centre(x0) - s / 2, cell_centre(x1) + s / 2, cell_centre(y0) - s / 2,
                         cell_centre(y1) + s / 2};
    BoxEdgeOptions options;
    options.view_heading_rad = 0.0;
    options.view_path_point_m = {0.0, 0.0};  // the rail runs along x through the box
    const BoxEdgeFit by_stripes = fit_box_edges(readings, frame, s, true, options, cells);
    // A rail beyond the +y side: the beams meet that face, it keeps the quantile.
    options.view_path_point_m = {0.0, 0.3};
    EXPECT_EQ(fit_box_edges(readings, frame, s, true, options, cells).stripe, (std::array<bool, 4>{false, false, true, false}));
    options.stripe_chords = false;
    const BoxEdgeFit by_quantile = fit_box_edges(readings, frame, s, true, options, cells);
    ASSERT_TRUE(by_stripes.ok && by_quantile.ok);
    EXPECT_EQ(by_stripes.stripe, (std::array<bool, 4>{false, false, true, true}));
    EXPECT_EQ(by_quantile.stripe, (std::array<bool, 4>{false, false, false, false}));
    stripe_errors.push_back(by_stripes.width_m - (y1 - y0));
    quantile_errors.push_back(by_quantile.width_m - (y1 - y0));
  }
  const auto mean = [](const std::vector<double>& v) { return std::accumulate(v.begin(), v.end(), 0.0) / v.size(); };
  const auto p90 = [](std::vector<double> v) {
    for (double& e : v) e = std::abs(e);
    std::sort(v.begin(), v.end());
    return v[v.size() * 9 / 10];
  };
  // The quantile: 3.6 mm short on average, 6.3 mm at the 90th percentile.
  // The stripes: 0.7 mm short, 2.3 mm: the outermost beam on the top lies
  // up to a spacing inside the edge, which the estimate does not model.
  EXPECT_LT(mean(quantile_errors), -0.003);
  EXPECT_NEAR(mean(stripe_errors), 0.0, spacing / 2);
  EXPECT_LT(p90(stripe_errors), 0.003);
  EXPECT_GT(p90(quantile_errors), 0.005);
}

TEST(BoxEdges, TooFewReadingsOnASideIsNoFit) {
  const std::vector<Eigen::Vector2d> readings{{-0.05, 0.0}, {-0.05, 0.01}, {0.05, 0.0}, {0.05, 0.01}, {0.0, -0.04}};
  EXPECT_FALSE(fit_box_edges(readings, {0.0, -0.05, 0.05, -0.04, 0.04}, 0.01, true).ok);
}

// The layers only watch the update: every other layer of the map is the
// same bit for bit with and without them, on URG scans with mixed pixels.
TEST(BoxEdges, TopPointLayersLeaveTheHeightsBitIdentical) {
  const Scene scene = parse_scene_yaml(off_grid_scene(0.4), "off-grid scene");
  const std::vector<TrunkPose> poses = cart_rail_poses(*scene.cart_rail);
  PipelineOptions options;
  options.mapper.follow_robot = false;
  options.mapper.grid = {160, 0.01};
  options.filters = {ScanFilterKind::range_clustering, ScanFilterKind::scan_sequence};
  PipelineOptions with_layers = options;
  declare_top_point_layers(with_layers.mapper.grid);
  MappingPipeline plain(options), kept(with_layers);
  for (MappingPipeline* p : {&plain, &kept}) p->mapper().map().move_to(0.9, 0.0);
  TopPointObserver observer(kept);
  UrgSimulator simulator(scene, options.urg, UrgSimOptions{}, 3, std::make_unique<FootprintBeamModel>());
  UrgRawScan raw;
  for (std::size_t k = 0; k < poses.size(); ++k) {
    simulator.scan(poses[k], options.mount, static_cast<double>(k) * options.urg.scan_period_s, raw);
    plain.add(raw, poses[k]);
    kept.add(raw, poses[k]);
  }
  plain.finish();
  kept.finish();
  const ElevationMap& a = plain.mapper().map();
  const ElevationMap& b = kept.mapper().map();
  ASSERT_EQ(b.layer_count(), a.layer_count() + 2);
  const std::size_t cells = static_cast<std::size_t>(a.cells_per_side()) * static_cast<std::size_t>(a.cells_per_side());
  for (std::size_t k = 0; k < a.layer_count(); ++k) {
    // By name: the declared layers come before the foothold layers.
    const std::optional<std::size_t> in_b = b.find_layer(a.layer_spec(k).name);
    ASSERT_TRUE(in_b.has_value()) << a.layer_spec(k).name;
    EXPECT_EQ(std::memcmp(a.layer_bytes(k), b.layer_bytes(*in_b), cells * layer_type_bytes(a.layer_spec(k).type)), 0)
        << a.layer_spec(k).name;
  }
  // And the layers hold readings: each measured cell's point lies in it.
  const LayerId<float> x = b.layer<float>("top_point_x"), y = b.layer<float>("top_point_y");
  std::size_t measured = 0, inside = 0;
  for (int i = 0; i < b.cells_per_side(); ++i) {
    for (int j = 0; j < b.cells_per_side(); ++j) {
      const CellIndex c = b.cell_at_local(i, j);
      if (b.state(c) != CellState::measured) continue;
      ++measured;
      const float px = b.data(x)[b.slot(c)], py = b.data(y)[b.slot(c)];
      inside += b.cell_of(px, py) == c;
    }
  }
  EXPECT_GT(measured, 1000u);
  EXPECT_EQ(inside, measured);
}

// Boxes of 92, 137 and 148 mm at known places off the grid, square and
// turned, scanned by the simulated URG without mixed pixels: the widths
// (across the rail) come within 4 mm. The lengths (along the rail) come out
// long: the readings on the near face that range noise moves towards the
// sensor are also the higher ones, so eq. (10) keeps them and the face's
// edge cells hold readings in front of the face. Taking that face's edge
// at its readings' middle (facing_edge_quantile 0.5, with the view heading
// the cart rail passes on)
// shortens every length by at least a millimetre: 2.2-6.0 mm long with the
// outer envelope, within 3.4 mm with the middle (the far sides back down
// their beams, sensor_pitch_rad).
TEST(BoxEdges, OffGridBoxesMeasureWithinAFewMillimetres) {
  for (const double yaw : {0.0, 0.45}) {
    const Scene scene = parse_scene_yaml(off_grid_scene(yaw), "off-grid scene");
    CartRailOptions options;
    options.seed = 5;
    options.objects.edges.facing_edge_quantile = 0.5;
    options.sim.receiver.enabled = false;  // no mixed measurement of either kind: footprint or gain control
    const CartRailResult result = run_cart_rail(scene, options);
    // The same map with every side at the outer envelope (the default).
    ObjectMeasureOptions envelope = options.objects;
    envelope.edges.view_heading_rad = result.rail.yaw_rad;
    envelope.travel_point_m = {result.rail.start_x_m, result.rail.y_m};
    envelope.sensor_height_m = scanner_height_m(result, options);
    envelope.sensor_pitch_rad = scanner_pitch_rad(result, options);
    envelope.region_measured_only = true;  // a 10 mm step over 10 mm cells
    envelope.edges.facing_edge_quantile = envelope.edges.edge_quantile;
    const std::vector<ObjectMeasurement> blind = measure_objects(result.snapshot, scene, envelope);
    for (const std::string name : {"a", "b"}) {
      const ObjectMeasurement& m = named(result.objects, name);
      ASSERT_TRUE(m.found) << name;
      EXPECT_NEAR(m.measured.length_m, m.truth.length_m, 0.004) << name << " yaw " << yaw;
      EXPECT_NEAR(m.measured.width_m, m.truth.width_m, 0.004) << name << " yaw " << yaw;
      EXPECT_EQ(m.measured.length_m, m.edges_trimmed.length_m);
      const ObjectMeasurement& b = named(blind, name);
      EXPECT_GT(b.measured.length_m - b.truth.length_m, 0.002) << name << " yaw " << yaw;
      EXPECT_LT(m.measured.length_m, b.measured.length_m - 0.001) << name << " yaw " << yaw;
      EXPECT_EQ(m.measured.width_m, b.measured.width_m) << name << " yaw " << yaw;
    }
  }
}

// The truth names the objects and nothing else: the same map measured
// against a truth whose sizes and yaw are wrong (the centres kept, the yaw
// close enough to name the same axis the length) gives the same extents.
TEST(BoxEdges, TheTruthOnlySaysWhichObjectIsWhich) {
  const Scene scene = parse_scene_yaml(off_grid_scene(0.45), "off-grid scene");
  CartRailOptions options;
  options.seed = 9;
  options.mixed_pixels = true;
  options.filters = {ScanFilterKind::range_clustering, ScanFilterKind::scan_sequence};
  const CartRailResult result = run_cart_rail(scene, options);
  Scene wrong = scene;
  for (BoxObject& b : wrong.boxes) {
    b.length_m *= 2.5;
    b.width_m *= 0.4;
    b.yaw_rad += 0.3;
  }
  ObjectMeasureOptions objects = options.objects;
  objects.edges.view_heading_rad = result.rail.yaw_rad;  // as the cart rail measured them
  objects.travel_point_m = {result.rail.start_x_m, result.rail.y_m};
  objects.sensor_height_m = scanner_height_m(result, options);
  objects.sensor_pitch_rad = scanner_pitch_rad(result, options);
  objects.region_measured_only = true;
  const std::vector<ObjectMeasurement> again = measure_objects(result.snapshot, wrong, objects);
  ASSERT_EQ(again.size(), result.objects.size());
  for (std::size_t k = 0; k < again.size(); ++k) {
    ASSERT_TRUE(again[k].found);
    EXPECT_EQ(again[k].measured.length_m, result.objects[k].measured.length_m) << again[k].name;
    EXPECT_EQ(again[k].measured.width_m, result.objects[k].measured.width_m) << again[k].name;
    EXPECT_EQ(again[k].edges_untrimmed.length_m, result.objects[k].edges_untrimmed.length_m) << again[k].name;
  }
}

}  // namespace
}  // namespace stridemap
