// stridemap against OctoMap and a plain per-point implementation of the
// paper's update, on the same simulated scans, in one run (docs/
// performance.md, "Against OctoMap"). Built only where liboctomap-dev is
// installed; `make bench-compare` installs it and runs this.
//
// The scans: the URG-04LX simulator walking the rocky mock-up
// (scenes/rocky_mockup.yaml), true poses, seed 1 (simulator results). Each
// contender maps the same scans from the start:
//   stridemap  UrgModel::to_beams + TerrainMapper::integrate (the packed path)
//   plain      the paper's update one point at a time, as written from the
//              paper: trig per beam, eq. (6) with its derivatives per point,
//              a cell found by floor and modulo
//   OctoMap    OcTree::insertPointCloud of the scan's map-frame points (the
//              points are made outside the timing: only the insertion counts)
// and then, at 1 cm, what users run: MappingPipeline (the tool's `map` and
// `live`, Python, the ROS node) with its defaults, with the paper's and
// with the urg filters, with the map read every 10th scan (a 1 Hz planner:
// the foothold layers brought up to date), and with the visibility
// clean-up, beside the packed core it is built on.
// Times are CPU time per scan (median of the repetitions for the fast ones).
//
//   compare [source-dir] [scans]
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <octomap/octomap.h>

#include "stridemap/config/scene_yaml.hpp"
#include "stridemap/core/terrain_mapper.hpp"
#include "stridemap/pipeline/mapping_pipeline.hpp"
#include "stridemap/sensors/urg04lx.hpp"
#include "stridemap/sim/urg_simulator.hpp"
#include "stridemap/sim/walk_motion.hpp"
#include "test_paths.hpp"

using namespace stridemap;

namespace {

double cpu_s() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

struct Recorded {
  UrgRawScan raw;
  TrunkPose pose;
};

MapperOptions mapper_options(double cell_m) {
  MapperOptions o;
  o.grid = {static_cast<int>(std::lround(1.0 / cell_m)), cell_m};  // a 1 m window, as the paper's
  o.window_ahead_m = 0.3;
  return o;
}

// Runs `body` (one pass over every scan) `repeats` times; CPU seconds per
// scan, the median pass.
template <class Body>
double per_scan_s(std::size_t scans, int repeats, Body body) {
  std::vector<double> passes;
  for (int r = 0; r < repeats; ++r) {
    const double start = cpu_s();
    body();
    passes.push_back((cpu_s() - start) / static_cast<double>(scans));
  }
  std::sort(passes.begin(), passes.end());
  return passes[passes.size() / 2];
}

// The paper's update written plainly: per point the beam's angle and its
// trig, the point through the composed rotation, eq. (6) with its partial
// derivatives evaluated for this point, Fig. 10's turn, then eq. (9), (10)
// on a cell found by floor and modulo.
class PlainMapper {
 public:
  PlainMapper(const UrgModel& model, const MapperOptions& options, const SensorMount& mount)
      : model_(model), options_(options), mount_(mount), n_(options.grid.cells_per_side),
        cell_m_(options.grid.cell_size_m), cells_(static_cast<std::size_t>(n_ * n_)) {}

  void integrate(const UrgRawScan& raw, const TrunkPose& pose) {
    const double travel = previous_ ? std::hypot(pose.x_m - previous_->x_m, pose.y_m - previous_->y_m) : 0.0;
    const double turn = previous_ ? std::remainder(pose.yaw_rad - previous_->yaw_rad, 2.0 * M_PI) : 0.0;
    previous_ = pose;
    const Eigen::Matrix3d rotation = sensor_to_map_rotation(pose, mount_);
    const Eigen::Vector3d origin = sensor_origin_in_map(pose, mount_);
    const auto centre_x = static_cast<long>(std::floor((pose.x_m + options_.window_ahead_m * std::cos(pose.yaw_rad)) / cell_m_));
    const auto centre_y = static_cast<long>(std::floor((pose.y_m + options_.window_ahead_m * std::sin(pose.yaw_rad)) / cell_m_));
    for (std::size_t i = 0; i < raw.values_mm.size(); ++i) {
      if (model_.classify(raw.values_mm[i]) != UrgValueClass::valid) continue;
      const double r = model_.calibration().corrected_m(raw.values_mm[i] * 0.001);
      const double dr = UrgModel::spec_range_error_m(r);
      const double angle = model_.parameters().step_angle_rad(raw.first_step + static_cast<double>(i) * raw.cluster);
      const Eigen::Vector3d p = origin + rotation * Eigen::Vector3d(r * std::cos(angle), r * std::sin(angle), 0.0);
      const ElevationPartials partials =
          beam_elevation_partials(r, angle, pose.pitch_rad, pose.roll_rad, mount_);
      const double gamma = scan_plane_inclination_rad(pose.pitch_rad, pose.roll_rad, mount_);
      double d = travel;
      if (options_.update.use_turning_term) {
        d += turning_travel_m(std::hypot(p.x() - origin.x(), p.y() - origin.y()), 0.0, turn);
      }
      const double dz_max = laser_max_elevation_change(partials, dr, d, gamma, options_.update);
      const long cx = static_cast<long>(std::floor(p.x() / cell_m_)), cy = static_cast<long>(std::floor(p.y() / cell_m_));
      if (std::labs(cx - centre_x) >= n_ / 2 || std::labs(cy - centre_y) >= n_ / 2) continue;
      Cell& cell = cells_[static_cast<std::size_t>((((cx % n_) + n_) % n_) * n_ + (((cy % n_) + n_) % n_))];
      const double h = p.z();
      if (cell.certainty == 0.0) {
        cell = {h, options_.update.certainty_increment};
      } else if (std::abs(h - cell.elevation) <= dz_max) {
        cell.certainty = std::min(cell.certainty + options_.update.certainty_increment, options_.update.certainty_max);
        cell.elevation = std::max(cell.elevation, h);
      } else {
        cell.elevation = std::max(cell.elevation, h);
      }
    }
  }
  std::size_t measured() const {
    return static_cast<std::size_t>(std::count_if(cells_.begin(), cells_.end(), [](const Cell& c) { return c.certainty > 0; }));
  }

 private:
  struct Cell {
    double elevation = 0.0;
    double certainty = 0.0;
  };
  const UrgModel& model_;
  MapperOptions options_;
  SensorMount mount_;
  long n_;
  double cell_m_;
  std::vector<Cell> cells_;
  std::optional<TrunkPose> previous_;
};

// The pipeline over every scan from a fresh map; the map read (map(): the
// derived layers brought up to date) after every read_every-th scan.
double pipeline_per_scan_s(const std::vector<Recorded>& scans, const PipelineOptions& options, int read_every,
                           int repeats) {
  return per_scan_s(scans.size(), repeats, [&] {
    MappingPipeline pipeline(options);
    int added = 0;
    for (const Recorded& s : scans) {
      pipeline.add(s.raw, s.pose);
      if (read_every > 0 && ++added % read_every == 0) (void)pipeline.map().cells_per_side();
    }
    pipeline.finish();
  });
}

}  // namespace

int main(int argc, char** argv) {
  const std::string source_dir = argc > 1 ? argv[1] : STRIDEMAP_SOURCE_DIR;
  const int scan_count = argc > 2 ? std::atoi(argv[2]) : 300;
  const Scene scene = load_scene_yaml(source_dir + "/scenes/rocky_mockup.yaml");
  const WalkMotion motion(scene);
  const SensorMount mount;
  const UrgParameters urg;
  UrgSimulator simulator(scene, urg, UrgSimOptions{}, 1);
  std::vector<Recorded> scans(static_cast<std::size_t>(scan_count));
  std::size_t valid = 0;
  const UrgModel model(urg);
  for (std::size_t k = 0; k < scans.size(); ++k) {
    const double t = std::min(0.1 * static_cast<double>(k), motion.duration_s());
    scans[k].pose = motion.pose_at(t);
    simulator.scan(scans[k].pose, mount, 0.1 * static_cast<double>(k + 1), scans[k].raw);
    for (std::uint32_t v : scans[k].raw.values_mm) valid += model.classify(v) == UrgValueClass::valid ? 1 : 0;
  }
  std::printf("%zu simulated URG-04LX scans of the rocky mock-up walk (seed 1), %.0f valid points per scan\n\n",
              scans.size(), static_cast<double>(valid) / static_cast<double>(scans.size()));
  std::printf("| cell | stridemap per scan | plain per-point | OctoMap insertPointCloud | plain / stridemap | OctoMap / stridemap |\n");
  std::printf("| --- | --- | --- | --- | --- | --- |\n");
  std::vector<std::pair<std::string, double>> users_run;
  for (const double cell_m : {0.01, 0.02}) {
    const MapperOptions options = mapper_options(cell_m);
    PlanarBeams beams;
    const double stride_s = per_scan_s(scans.size(), 21, [&] {
      TerrainMapper mapper(options, mount);
      for (const Recorded& s : scans) {
        model.to_beams(s.raw, beams);
        mapper.integrate(beams, s.pose);
      }
    });
    const double plain_s = per_scan_s(scans.size(), 5, [&] {
      PlainMapper plain(model, options, mount);
      for (const Recorded& s : scans) plain.integrate(s.raw, s.pose);
    });
    // OctoMap gets each scan's points in the map frame, made beforehand.
    std::vector<octomap::Pointcloud> clouds(scans.size());
    std::vector<octomap::point3d> origins(scans.size());
    PlanarScan planar;
    for (std::size_t k = 0; k < scans.size(); ++k) {
      model.to_planar_scan(scans[k].raw, planar);
      const Eigen::Vector3d o = sensor_origin_in_map(scans[k].pose, mount);
      origins[k] = octomap::point3d(static_cast<float>(o.x()), static_cast<float>(o.y()), static_cast<float>(o.z()));
      for (std::size_t i = 0; i < planar.size(); ++i) {
        if (!std::isfinite(planar.range_m[i])) continue;
        const Eigen::Vector3d p = sensor_point_to_map(
            planar.range_m[i] * Eigen::Vector3d(std::cos(planar.angle_rad[i]), std::sin(planar.angle_rad[i]), 0.0),
            scans[k].pose, mount);
        clouds[k].push_back(static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z()));
      }
    }
    const double octomap_s = per_scan_s(scans.size(), 1, [&] {
      octomap::OcTree tree(cell_m);
      for (std::size_t k = 0; k < scans.size(); ++k) tree.insertPointCloud(clouds[k], origins[k]);
    });
    std::printf("| %.0f cm | %.1f us | %.1f us | %.2f ms | %.0fx | %.0fx |\n", cell_m * 100.0, stride_s * 1e6,
                plain_s * 1e6, octomap_s * 1e3, plain_s / stride_s, octomap_s / stride_s);
    std::fflush(stdout);
    if (cell_m != 0.01) continue;
    users_run.push_back({"packed core (to_beams + TerrainMapper::integrate)", stride_s});
    users_run.push_back({"plain per-point update", plain_s});
    users_run.push_back({"OctoMap insertPointCloud", octomap_s});
    PipelineOptions defaults;
    defaults.mapper = options;
    defaults.mount = mount;
    defaults.urg = urg;
    users_run.push_back({"pipeline, defaults", pipeline_per_scan_s(scans, defaults, 0, 11)});
    for (const char* filters : {"paper", "urg"}) {
      PipelineOptions filtered = defaults;
      filtered.filters = parse_scan_filter_list(std::string_view(filters));
      users_run.push_back({std::string("pipeline, --filters ") + filters, pipeline_per_scan_s(scans, filtered, 0, 11)});
    }
    users_run.push_back({"pipeline, map read every 10th scan", pipeline_per_scan_s(scans, defaults, 10, 11)});
    PipelineOptions cleared = defaults;
    cleared.visibility.enabled = true;
    users_run.push_back({"pipeline, visibility clean-up on", pipeline_per_scan_s(scans, cleared, 0, 11)});
  }
  // Ratios within one run of one process, so the machine's speed cancels.
  const double core_s = users_run.front().second;
  double octomap_s = 0.0;
  for (const auto& [name, seconds] : users_run)
    if (name.rfind("OctoMap", 0) == 0) octomap_s = seconds;
  std::printf("\nWhat users run, 1 cm cells, the same scans:\n\n");
  std::printf("| path | per scan | / packed core | OctoMap / this |\n| --- | --- | --- | --- |\n");
  for (const auto& [name, seconds] : users_run) {
    std::printf("| %s | %.1f us | %.2fx | %.0fx |\n", name.c_str(), seconds * 1e6, seconds / core_s, octomap_s / seconds);
  }
  return 0;
}
