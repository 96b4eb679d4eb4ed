// The packed per-point path (TerrainMapper::integrate, core/planar_beams.hpp)
// against a plain per-point implementation of the same math written here:
// every layer of every cell bit for bit, and the same counts, over scans
// with every kind of bad beam, turning and jumping poses, both elevation
// rules, the full mount and a pose with z, a window that moves, and a
// layer a user declared.
#include <cmath>
#include <cstring>
#include <limits>
#include <numbers>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "stridemap/core/terrain_mapper.hpp"

namespace stridemap {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

// The update of section 5.2 one point at a time, as the library did before
// the packed path: eq. (5) for the point, eq. (6), (7) and Fig. 10 for
// Delta z_max, then eq. (9), (10) on the cell.
class ReferenceMapper {
 public:
  ReferenceMapper(const MapperOptions& options, const SensorMount& mount)
      : options_(options), mount_(mount), map_(options.grid) {}

  ScanStats integrate(const PlanarScan& scan, const TrunkPose& pose) {
    ScanStats stats;
    stats.beams = scan.size();
    if (!pose_is_finite(pose) || (previous_time_ && !(scan.time_s > *previous_time_))) return stats;
    if (options_.follow_robot) {
      map_.move_to(pose.x_m + options_.window_ahead_m * std::cos(pose.yaw_rad),
                   pose.y_m + options_.window_ahead_m * std::sin(pose.yaw_rad));
    }
    ScanMotion motion;
    if (previous_pose_) {
      const Eigen::Vector3d a = sensor_origin_in_map(*previous_pose_, mount_), b = sensor_origin_in_map(pose, mount_);
      motion = {std::hypot(b.x() - a.x(), b.y() - a.y()),
                std::remainder(pose.yaw_rad - previous_pose_->yaw_rad, 2.0 * std::numbers::pi)};
    }
    const Eigen::Matrix3d rotation = sensor_to_map_rotation(pose, mount_);
    const ElevationPartials front = beam_elevation_partials(1.0, 0.0, pose.pitch_rad, pose.roll_rad, mount_);
    const ElevationPartials left =
        beam_elevation_partials(1.0, std::numbers::pi / 2, pose.pitch_rad, pose.roll_rad, mount_);
    const ElevationPartials lever = sensor_origin_elevation_partials(pose, mount_);
    const MaxElevationChange bound(motion, scan_plane_inclination_rad(pose.pitch_rad, pose.roll_rad, mount_), mount_,
                                   options_.update, pose.yaw_rad);
    const Eigen::Vector3d origin = sensor_origin_in_map(pose, mount_);
    for (std::size_t i = 0; i < scan.size(); ++i) {
      const double r = scan.range_m[i], dr = scan.range_error_m[i], t = scan.angle_rad[i];
      if (!std::isfinite(r) || r <= 0.0) {
        ++stats.invalid_range;
        continue;
      }
      if (!std::isfinite(t) || !std::isfinite(dr) || dr < 0.0) {
        ++stats.invalid_beam;
        continue;
      }
      const double ct = std::cos(t), st = std::sin(t);
      const Eigen::Vector3d offset = r * (ct * rotation.col(0) + st * rotation.col(1));
      ElevationPartials p;
      p.d_range = ct * front.d_range + st * left.d_range;
      p.d_pitch_m_per_rad = lever.d_pitch_m_per_rad + r * (ct * front.d_pitch_m_per_rad + st * left.d_pitch_m_per_rad);
      p.d_roll_m_per_rad = lever.d_roll_m_per_rad + r * (ct * front.d_roll_m_per_rad + st * left.d_roll_m_per_rad);
      p.d_alpha_m_per_rad = r * (ct * front.d_alpha_m_per_rad + st * left.d_alpha_m_per_rad);
      const double dz_max = bound.at(elevation_error_bound_m(p, dr, options_.update), offset);
      const Eigen::Vector3d point = origin + offset;
      std::size_t s = 0;
      if (!(std::abs(point.x()) < 1e6 && std::abs(point.y()) < 1e6 && std::abs(point.z()) < 1e6) ||
          !map_.slot_at(point.x(), point.y(), s)) {
        ++stats.outside_map;
        continue;
      }
      const CellUpdate result = update_cell(
          {map_.elevation_data()[s], map_.certainty_data()[s], map_.state_data()[s], map_.pending_elevation_data()[s],
           map_.contradiction_data()[s], map_.mean_elevation_data()[s], map_.mean_count_data()[s]},
          static_cast<float>(point.z()), static_cast<float>(dz_max), options_.update);
      ++stats.integrated;
      if (result == CellUpdate::first) ++stats.first;
      if (result == CellUpdate::plausible) ++stats.plausible;
      if (result == CellUpdate::implausible) ++stats.implausible;
      if (result == CellUpdate::replaced) ++stats.replaced;
    }
    previous_pose_ = pose;
    previous_time_ = scan.time_s;
    return stats;
  }
  const ElevationMap& map() const { return map_; }

 private:
  MapperOptions options_;
  SensorMount mount_;
  ElevationMap map_;
  std::optional<TrunkPose> previous_pose_;
  std::optional<double> previous_time_;
};

void expect_same_maps(const ElevationMap& a, const ElevationMap& b, int scan) {
  ASSERT_EQ(a.layer_count(), b.layer_count());
  ASSERT_EQ(a.min_cell(), b.min_cell());
  const std::size_t cells = static_cast<std::size_t>(a.cells_per_side()) * static_cast<std::size_t>(a.cells_per_side());
  for (std::size_t k = 0; k < a.layer_count(); ++k) {
    EXPECT_EQ(std::memcmp(a.layer_bytes(k), b.layer_bytes(k), cells * layer_type_bytes(a.layer_spec(k).type)), 0)
        << "layer " << a.layer_spec(k).name << " differs after scan " << scan;
  }
}

void expect_same_stats(const ScanStats& a, const ScanStats& b, int scan) {
  EXPECT_EQ(a.beams, b.beams) << scan;
  EXPECT_EQ(a.integrated, b.integrated) << scan;
  EXPECT_EQ(a.first, b.first) << scan;
  EXPECT_EQ(a.plausible, b.plausible) << scan;
  EXPECT_EQ(a.implausible, b.implausible) << scan;
  EXPECT_EQ(a.replaced, b.replaced) << scan;
  EXPECT_EQ(a.invalid_range, b.invalid_range) << scan;
  EXPECT_EQ(a.invalid_beam, b.invalid_beam) << scan;
  EXPECT_EQ(a.outside_map, b.outside_map) << scan;
}

// A rough floor seen by a URG-sized fan, with bad beams sprinkled in.
void fill_scan(PlanarScan& scan, std::mt19937_64& rng, const SensorMount& mount, bool new_angles) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const std::size_t beams = 682;
  scan.resize(beams);
  for (std::size_t i = 0; i < beams; ++i) {
    if (new_angles) scan.angle_rad[i] = (static_cast<double>(i) - 340.0) * 2.0 * std::numbers::pi / 1024.0;
    const double down = std::cos(scan.angle_rad[i]) * std::sin(mount.pitch_rad);
    scan.range_m[i] = down > 0.05 ? mount.height_m / down * (0.7 + 0.35 * u(rng)) : kNaN;
    scan.range_error_m[i] = scan.range_m[i] > 1.0 ? 0.01 * scan.range_m[i] : 0.01;
    const double bad = u(rng);
    if (bad < 0.02) scan.range_m[i] = kInf;
    else if (bad < 0.04) scan.range_m[i] = -0.5;
    else if (bad < 0.05) scan.range_m[i] = 0.0;
    else if (bad < 0.06) scan.range_error_m[i] = kNaN;
    else if (bad < 0.07) scan.range_error_m[i] = -0.01;
    else if (bad < 0.075) scan.range_error_m[i] = kInf;
    else if (bad < 0.08) scan.range_m[i] = 1e300;  // a point far beyond any window
  }
  if (new_angles && u(rng) < 0.5) scan.angle_rad[7] = kNaN;
}

struct Case {
  ElevationRule rule;
  bool full_mount;
  bool pose_z;
  bool follow;
  bool user_layer;
};

void run_case(const Case& c, unsigned seed) {
  SensorMount mount;
  if (c.full_mount) {
    mount.roll_rad = 0.087;
    mount.yaw_rad = 0.17;
    mount.forward_offset_m = 0.1;
    mount.lateral_offset_m = -0.03;
  }
  MapperOptions options;
  options.grid = {100, 0.01};
  options.follow_robot = c.follow;
  options.window_ahead_m = 0.3;
  options.update.elevation_rule = c.rule;
  if (c.user_layer) options.grid.extra_layers.push_back({"hit_flag", LayerType::u8, 7.0, "", "a user's layer", true});
  TerrainMapper packed(options, mount);
  TerrainMapper per_point(options, mount);  // the generic source path: a sink forces it
  ReferenceMapper reference(options, mount);
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> tilt(0.0, 0.03);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  PlanarScan scan;
  TrunkPose pose;
  if (c.pose_z) pose.z_m = 0.05;
  for (int k = 0; k < 120; ++k) {
    fill_scan(scan, rng, mount, k == 0 || u(rng) < 0.1);
    scan.time_s = 0.1 * (k + 1);
    pose.x_m += 0.004 + 0.01 * u(rng);
    pose.y_m += 0.003 * (u(rng) - 0.5);
    pose.yaw_rad += u(rng) < 0.05 ? 2.0 : 0.01 * (u(rng) - 0.3);  // now and then a jump beyond a quarter turn
    if (u(rng) < 0.05) pose.yaw_rad = 0.0;                        // and none at all
    pose.pitch_rad = tilt(rng);
    pose.roll_rad = tilt(rng);
    if (c.pose_z) pose.z_m = 0.05 + 0.01 * u(rng);
    pose.height_change_m = 0.01 * (u(rng) - 0.5);
    const ScanStats a = packed.integrate(scan, pose);
    const ScanStats b = per_point.integrate(scan, pose, [](std::size_t, const Eigen::Vector3d&, const SensorPoint&) {});
    const ScanStats r = reference.integrate(scan, pose);
    expect_same_stats(a, r, k);
    expect_same_stats(b, r, k);
    expect_same_maps(packed.map(), reference.map(), k);
    expect_same_maps(per_point.map(), reference.map(), k);
    if (::testing::Test::HasFailure()) return;
  }
  EXPECT_GT(packed.totals().integrated, 5000u);
  EXPECT_GT(packed.totals().implausible, 0u);
}

TEST(PackedBeams, MapsMatchThePlainPerPointUpdateBitForBit) {
  for (unsigned seed : {1u, 2u, 3u}) {
    run_case({ElevationRule::paper_highest, false, false, true, false}, seed);
    run_case({ElevationRule::gated_highest, false, false, true, false}, seed);
    run_case({ElevationRule::paper_highest, true, true, true, false}, seed);
    run_case({ElevationRule::gated_highest, true, false, false, true}, seed);
    if (HasFailure()) return;
  }
}

TEST(PackedBeams, AUserLayerIsKeptAndResetByTheWindow) {
  MapperOptions options;
  options.window_ahead_m = 0.3;
  options.grid.extra_layers.push_back({"visits", LayerType::u16, 5.0, "", "a user's counter", true});
  TerrainMapper mapper(options, SensorMount{});
  const LayerId<std::uint16_t> visits = mapper.map().layer<std::uint16_t>("visits");
  std::mt19937_64 rng(4);
  PlanarScan scan;
  TrunkPose pose;
  for (int k = 0; k < 50; ++k) {
    fill_scan(scan, rng, SensorMount{}, k == 0);
    scan.time_s = k + 1.0;
    pose.x_m += 0.02;
    mapper.integrate(scan, pose);
    mapper.map().data(visits)[0] = 9;  // the user's own writes
  }
  const std::size_t cells = 100 * 100;
  std::size_t reset = 0;
  for (std::size_t s = 0; s < cells; ++s) reset += mapper.map().data(visits)[s] == 5 ? 1 : 0;
  EXPECT_EQ(mapper.map().data(visits)[0], 9);
  EXPECT_EQ(reset, cells - 1);  // the update never writes a user's layer
}

// Far from the origin the window's indices no longer fit 32 bits and the
// packed path takes its per-point way: the same map still.
TEST(PackedBeams, AWindowFarFromTheOriginGivesTheSameMap) {
  MapperOptions options;
  options.grid = {1000, 5e-4};  // 0.5 m
  options.window_ahead_m = 0.3;
  SensorMount mount;
  TerrainMapper packed(options, mount);
  ReferenceMapper reference(options, mount);
  std::mt19937_64 rng(5);
  PlanarScan scan;
  TrunkPose pose;
  pose.x_m = 8.0e5;  // 1.6e9 cells of 0.5 mm
  pose.y_m = -6.0e5;
  for (int k = 0; k < 10; ++k) {
    fill_scan(scan, rng, mount, k == 0);
    scan.time_s = k + 1.0;
    pose.x_m += 0.01;
    expect_same_stats(packed.integrate(scan, pose), reference.integrate(scan, pose), k);
    expect_same_maps(packed.map(), reference.map(), k);
  }
  EXPECT_GT(packed.totals().integrated, 0u);
}

// A window across x = 1e6 m and y = -1e6 m (still within 32-bit indices at
// 1 cm): the first pass keeps its x and y range checks there, so points
// beyond them stay out of the map as apply() keeps them out.
TEST(PackedBeams, AWindowAcrossTheCoordinateLimitGivesTheSameMap) {
  MapperOptions options;
  options.grid = {100, 0.01};
  options.window_ahead_m = 0.3;
  SensorMount mount;
  TerrainMapper packed(options, mount);
  ReferenceMapper reference(options, mount);
  std::mt19937_64 rng(6);
  PlanarScan scan;
  TrunkPose pose;
  pose.x_m = 1.0e6 - 0.45;
  pose.y_m = -1.0e6 + 0.1;
  pose.yaw_rad = -0.6;  // the scan line runs across both limits
  std::size_t outside = 0;
  for (int k = 0; k < 40; ++k) {
    fill_scan(scan, rng, mount, k == 0);
    scan.time_s = k + 1.0;
    pose.x_m += 0.005;
    const ScanStats a = packed.integrate(scan, pose);
    expect_same_stats(a, reference.integrate(scan, pose), k);
    expect_same_maps(packed.map(), reference.map(), k);
    outside += a.outside_map;
    if (HasFailure()) return;
  }
  EXPECT_GT(packed.totals().integrated, 1000u);
  EXPECT_GT(outside, 1000u);
  // Nothing beyond the limits was written: the cells there stay unknown.
  const ElevationMap& map = packed.map();
  for (std::int64_t x = map.min_cell().x; x < map.min_cell().x + map.cells_per_side(); ++x) {
    for (std::int64_t y = map.min_cell().y; y < map.min_cell().y + map.cells_per_side(); ++y) {
      if (x >= 100000000 || y < -100000000) {
        EXPECT_NE(map.state(CellIndex{x, y}), CellState::measured) << x << ", " << y;
      }
    }
  }
}

}  // namespace
}  // namespace stridemap
