// A scanner mounted with roll and yaw, simulated and mapped with the same
// mount: the map holds the scene's heights. Mapped as if the mount had no
// roll or yaw, the same scans give a wrong map, so the check has teeth.
#include <cmath>
#include <numbers>
#include <optional>
#include <vector>

#include <gtest/gtest.h>

#include "stridemap/core/terrain_mapper.hpp"
#include "stridemap/sensors/urg04lx.hpp"
#include "stridemap/sensors/structured_light_mapping.hpp"
#include "stridemap/sim/structured_light_simulator.hpp"
#include "stridemap/sim/urg_simulator.hpp"

namespace stridemap {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;
constexpr double kBoxTop_m = 0.08;
constexpr double kSideMargin_m = 0.01;

Scene floor_with_box() {
  Scene scene;
  scene.terrain.reflectance = 0.5;
  BoxObject box;
  box.name = "box";
  box.center_x_m = 1.05;
  box.center_y_m = 0.05;
  box.length_m = 0.3;
  box.width_m = 0.4;
  box.height_m = kBoxTop_m;
  scene.boxes.push_back(box);
  return scene;
}

SensorMount rolled_and_yawed_mount() {
  SensorMount mount;
  mount.height_m = 0.26;
  mount.pitch_rad = 35 * kDeg;
  mount.roll_rad = 5 * kDeg;
  mount.yaw_rad = 10 * kDeg;
  mount.forward_offset_m = 0.05;
  mount.lateral_offset_m = -0.02;
  return mount;
}

struct MapCheck {
  int floor_cells = 0;
  int box_cells = 0;
  double worst_error_m = 0.0;
  Eigen::Vector2d worst_at = Eigen::Vector2d::Zero();
};

// Walks the trunk forward past the box, scanning with `true_mount`, and maps
// the scans with `mapper_mount`; then compares every measured cell that
// lies wholly on the floor or wholly on the box top with the scene.
MapCheck map_the_walk(const SensorMount& true_mount, const SensorMount& mapper_mount, std::optional<double> trunk_z_m) {
  const Scene scene = floor_with_box();
  UrgSimOptions ideal;
  ideal.enable_noise = false;
  ideal.enable_systematic_error = false;
  ideal.enable_dropouts = false;
  ideal.receiver.enabled = false;  // no range-intensity coupling either: an ideal sensor
  UrgSimulator sim(scene, UrgParameters{}, ideal, 7);
  const UrgModel model;
  MapperOptions options;
  options.grid.cells_per_side = 200;
  options.follow_robot = false;
  TerrainMapper mapper(options, mapper_mount);
  mapper.map().move_to(1.0, 0.0);

  UrgRawScan raw;
  PlanarScan scan;
  for (int k = 0; k < 90; ++k) {
    TrunkPose pose;
    pose.x_m = 0.01 * k;
    pose.y_m = 0.02;
    pose.yaw_rad = 0.03;
    pose.pitch_rad = 0.04;
    pose.roll_rad = -0.03;
    pose.z_m = trunk_z_m;
    sim.scan(pose, true_mount, 0.1 * k, raw);
    model.to_planar_scan(raw, scan);
    mapper.integrate(scan, pose);
  }

  MapCheck check;
  const ElevationMap& map = mapper.map();
  const double half = 0.5 * map.cell_size_m();
  for (int i = 0; i < map.cells_per_side(); ++i) {
    for (int j = 0; j < map.cells_per_side(); ++j) {
      const CellIndex cell = map.cell_at_local(i, j);
      if (map.state(cell) != CellState::measured) continue;
      const Eigen::Vector2d c = map.cell_center(cell);
      const double truth = scene.surface_height_at(c.x(), c.y());
      // A range rounded to the millimetre may carry a point of the box's
      // side into the floor cell next to it, where eq. (10) keeps it: leave
      // out the cells along the box's sides.
      bool uniform = true;
      for (const double dx : {-half - kSideMargin_m, 0.0, half + kSideMargin_m}) {
        for (const double dy : {-half - kSideMargin_m, 0.0, half + kSideMargin_m}) {
          uniform = uniform && scene.surface_height_at(c.x() + dx, c.y() + dy) == truth;
        }
      }
      if (!uniform) continue;
      (truth > 0.0 ? check.box_cells : check.floor_cells) += 1;
      const double error = std::abs(map.elevation(cell) - truth);
      if (error > check.worst_error_m) {
        check.worst_error_m = error;
        check.worst_at = c;
      }
    }
  }
  return check;
}

TEST(FullMountMapping, ARolledAndYawedScannerMapsFloorAndBoxAtTheirHeights) {
  const SensorMount mount = rolled_and_yawed_mount();
  const MapCheck check = map_the_walk(mount, mount, std::nullopt);
  EXPECT_GT(check.floor_cells, 1000);
  EXPECT_GT(check.box_cells, 100);
  // Ideal ranges come in whole millimetres; nothing else is lost.
  EXPECT_LT(check.worst_error_m, 0.004) << "at " << check.worst_at.transpose();
}

TEST(FullMountMapping, IgnoringTheMountRollAndYawGivesAWrongMap) {
  SensorMount paper_only = rolled_and_yawed_mount();
  paper_only.roll_rad = 0.0;
  paper_only.yaw_rad = 0.0;
  const MapCheck check = map_the_walk(rolled_and_yawed_mount(), paper_only, std::nullopt);
  EXPECT_GT(check.worst_error_m, 0.02);
}

TEST(FullMountMapping, APoseWithZPlacesTheSensorByTheFullTransform) {
  SensorMount mount = rolled_and_yawed_mount();
  mount.height_m = 0.08;  // above a trunk centre 0.18 m over the floor
  const MapCheck check = map_the_walk(mount, mount, 0.18);
  EXPECT_GT(check.floor_cells, 1000);
  EXPECT_GT(check.box_cells, 100);
  EXPECT_LT(check.worst_error_m, 0.004) << "at " << check.worst_at.transpose();
}

// The structured-light sensor: the stripe the simulator sees with a rolled
// and yawed mount, turned into map points with the same mount, lies on the
// scene; the largest height error over one frame's points.
double worst_stripe_point_error_m(const SensorMount& true_mount, const SensorMount& mapper_mount,
                                  std::optional<double> trunk_z_m, std::size_t& points_checked) {
  Scene scene;
  scene.terrain.reflectance = 0.5;
  BoxObject box;
  box.name = "box";
  box.center_x_m = 0.27;
  box.center_y_m = 0.0;
  box.length_m = 0.1;
  box.width_m = 0.12;
  box.height_m = 0.03;
  box.reflectance = 0.8;
  scene.boxes.push_back(box);
  StructuredLightParameters truth;  // Ragno's sensor
  truth.mount.roll_rad = true_mount.roll_rad;
  truth.mount.yaw_rad = true_mount.yaw_rad;
  truth.mount.forward_offset_m = true_mount.forward_offset_m;
  StructuredLightParameters mapped = truth;
  mapped.mount.roll_rad = mapper_mount.roll_rad;
  mapped.mount.yaw_rad = mapper_mount.yaw_rad;
  StructuredLightSimulator sim(scene, truth);
  StructuredLightFrameTruth frame;
  TrunkPose pose;
  pose.x_m = 0.02;
  pose.pitch_rad = 2 * kDeg;
  pose.roll_rad = -1.5 * kDeg;
  pose.z_m = trunk_z_m;
  sim.simulate(pose, frame);
  EXPECT_GT(frame.visible, 500u) << "no_surface " << frame.no_surface << " hidden " << frame.hidden_from_camera
                                 << " outside_image " << frame.outside_image << " outside_fan " << frame.outside_fan;
  std::vector<MapPoint> points;
  const StructuredLightModel model(mapped);
  const StripeConversionStats stats = stripe_to_map_points(model, frame.stripe, pose, ScanMotion{}, UpdateOptions{}, points);
  double worst = 0.0;
  points_checked = 0;
  for (const MapPoint& p : points) {
    const double truth_m = scene.surface_height_at(p.x_m, p.y_m);
    // Points within a millimetre of the box's sides may land on either height.
    const bool near_edge = std::abs(std::abs(p.x_m - box.center_x_m) - 0.05) < 0.001 ||
                           std::abs(std::abs(p.y_m - box.center_y_m) - 0.06) < 0.001;
    if (near_edge) continue;
    worst = std::max(worst, std::abs(p.elevation_m - truth_m));
    ++points_checked;
  }
  EXPECT_EQ(stats.converted, frame.stripe.size()) << stats.not_finite << " " << stats.outside_image << " "
                                                 << stats.no_intersection << " " << stats.pose_rejected;
  EXPECT_EQ(points.size(), stats.converted);
  return worst;
}

TEST(FullMountMapping, AStructuredLightSensorWithMountRollAndYawMapsTheStripeOnTheScene) {
  const SensorMount mount = rolled_and_yawed_mount();
  std::size_t checked = 0;
  EXPECT_LT(worst_stripe_point_error_m(mount, mount, std::nullopt, checked), 1e-9);
  EXPECT_GT(checked, 500u);
  EXPECT_LT(worst_stripe_point_error_m(mount, mount, 0.005, checked), 1e-9);  // trunk point near the ground
  EXPECT_GT(checked, 500u);
  SensorMount paper_only = mount;
  paper_only.roll_rad = 0.0;
  paper_only.yaw_rad = 0.0;
  EXPECT_GT(worst_stripe_point_error_m(mount, paper_only, std::nullopt, checked), 0.005);
}

}  // namespace
}  // namespace stridemap
