// Would single precision in the per-point path change the maps?
// (docs/performance.md, "Single precision".) The same raw URG-04LX scans go
// through four mappers:
//   packed  the library's path: UrgModel::to_beams + integrate(PlanarBeams), doubles
//   double  each point's offset and Delta z_max written out here in doubles
//           (PlanarBeamGeometry::point and MaxElevationChange::at) and fed to
//           integrate_points: checks that this harness is the library's path
//   float   the same arithmetic in floats: the beams (range, its error, cos,
//           sin), the scan's geometry and the addition of the sensor origin
//   offsets the offsets and Delta z_max in floats, the sensor origin added in
//           doubles (what a float path that keeps map positions in doubles does)
// and every known cell of the window is compared with packed's after every
// scan. The robot starts `start_x_m` from the map origin, because float's
// step grows with the coordinate (about 8 um at 100 m, 61 um at 1 km).
//
//   float_path_check [seeds] [scans]   (defaults 10 and 600)
// Prints one line per start distance and variant, summed over seeds and
// scans: cells compared (known in either map), cells known in both whose
// elevation differs (and the largest difference), cells known in one map
// only, and cells whose state or certainty differs. Exits 1 if the double
// harness differs from the library's path in any cell.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <vector>

#include "stridemap/core/max_elevation_change.hpp"
#include "stridemap/core/planar_scan_points.hpp"
#include "stridemap/core/sensor_transform.hpp"
#include "stridemap/core/terrain_mapper.hpp"
#include "stridemap/sensors/urg04lx.hpp"

using namespace stridemap;

namespace {

// As point_path_workload's: a floor with low steps, 3 mm of range noise.
UrgRawScan floor_scan(const UrgParameters& urg, const SensorMount& mount, std::mt19937_64& rng) {
  std::normal_distribution<double> noise_mm(0.0, 3.0);
  UrgRawScan raw;
  raw.first_step = urg.first_step;
  for (int step = urg.first_step; step <= urg.last_step; ++step) {
    const double down = std::cos(urg.step_angle_rad(step)) * std::sin(mount.pitch_rad);
    const double range_mm = down > 0.1 ? 1000.0 * mount.height_m / down * (step % 50 < 10 ? 0.8 : 1.0) : 0.0;
    raw.values_mm.push_back(range_mm > 0.0 ? static_cast<std::uint32_t>(std::lround(range_mm + noise_mm(rng))) : 0u);
  }
  return raw;
}

enum class Variant { double_harness, all_float, float_offsets };

// PlanarBeamGeometry::point and MaxElevationChange::at in scalar type T.
template <class T>
MapPoint map_point(const PlanarBeamGeometry& g, const MaxElevationChange& b, const UpdateOptions& o,
                   const Eigen::Vector3d& origin, double r_in, double dr_in, double ct_in, double st_in,
                   bool origin_in_t) {
  const auto t = [](double v) { return static_cast<T>(v); };
  const T r = t(r_in), dr = t(dr_in), ct = t(ct_in), st = t(st_in);
  const T ox = r * (ct * t(g.forward.x()) + st * t(g.left.x()));
  const T oy = r * (ct * t(g.forward.y()) + st * t(g.left.y()));
  const T oz = r * (ct * t(g.forward.z()) + st * t(g.left.z()));
  const T d_range = ct * t(g.at_front.d_range) + st * t(g.at_left.d_range);
  const T d_pitch = t(g.lever.d_pitch_m_per_rad) +
                    r * (ct * t(g.at_front.d_pitch_m_per_rad) + st * t(g.at_left.d_pitch_m_per_rad));
  const T d_roll = t(g.lever.d_roll_m_per_rad) +
                   r * (ct * t(g.at_front.d_roll_m_per_rad) + st * t(g.at_left.d_roll_m_per_rad));
  const T d_alpha = r * (ct * t(g.at_front.d_alpha_m_per_rad) + st * t(g.at_left.d_alpha_m_per_rad));
  const auto mag = [](T v) { return v < 0 ? -v : v; };
  const T error = mag(d_range * dr) + mag(d_roll) * t(o.max_roll_error_rad) + mag(d_pitch) * t(o.max_pitch_error_rad) +
                  mag(d_alpha) * t(o.max_mount_pitch_error_rad);
  T dz = t(b.travel_term_m()) + error;
  if (b.turn_term_per_m() != 0.0) {
    const T turn = t(b.turn_term_per_m()) * (std::sqrt(ox * ox + oy * oy) + t(b.turn_offset_m()));
    dz += turn != turn ? std::numeric_limits<T>::infinity() : turn;
    const T lateral = -t(b.sin_yaw()) * ox + t(b.cos_yaw()) * oy + t(b.mount_lateral_m());
    dz += t(b.lateral_term_per_m()) * mag(lateral);
  }
  MapPoint p;
  if (origin_in_t) {
    p.x_m = static_cast<double>(t(origin.x()) + ox);
    p.y_m = static_cast<double>(t(origin.y()) + oy);
    p.elevation_m = static_cast<double>(t(origin.z()) + oz);
  } else {
    p.x_m = origin.x() + static_cast<double>(ox);
    p.y_m = origin.y() + static_cast<double>(oy);
    p.elevation_m = origin.z() + static_cast<double>(oz);
  }
  p.max_elevation_change_m = static_cast<double>(dz);
  return p;
}

struct Difference {
  std::size_t compared = 0, elevation_differs = 0, known_in_one = 0, state_or_certainty_differs = 0;
  double largest_m = 0.0;  // between cells known in both
};

// Cells known in either map; both windows follow the same poses.
void compare(const ElevationMap& reference, const ElevationMap& other, Difference& d) {
  const std::size_t n = static_cast<std::size_t>(reference.cells_per_side()) * reference.cells_per_side();
  for (std::size_t s = 0; s < n; ++s) {
    const float a = reference.elevation_data()[s], b = other.elevation_data()[s];
    const bool known_a = a == a, known_b = b == b;
    if (!known_a && !known_b) continue;
    ++d.compared;
    if (known_a != known_b) {
      ++d.known_in_one;
    } else if (a != b) {
      ++d.elevation_differs;
      d.largest_m = std::max(d.largest_m, std::fabs(static_cast<double>(a) - b));
    }
    if (reference.state_data()[s] != other.state_data()[s] || reference.certainty_data()[s] != other.certainty_data()[s]) {
      ++d.state_or_certainty_differs;
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  const int seeds = argc > 1 ? std::atoi(argv[1]) : 10;
  const int scans = argc > 2 ? std::atoi(argv[2]) : 600;
  if (seeds < 1 || scans < 1) {
    std::fprintf(stderr, "usage: float_path_check [seeds >= 1] [scans >= 1]\n");
    return 2;
  }
  const UrgParameters urg;
  const SensorMount mount;
  const UrgModel model(urg);
  MapperOptions options;
  options.window_ahead_m = 0.3;
  const Variant variants[] = {Variant::double_harness, Variant::all_float, Variant::float_offsets};
  const char* names[] = {"double", "float", "offsets"};
  int status = 0;
  for (const double start_x_m : {0.0, 100.0, 1000.0}) {
    Difference totals[3];
    for (int seed = 1; seed <= seeds; ++seed) {
      TerrainMapper packed(options, mount);
      std::vector<TerrainMapper> others(3, TerrainMapper(options, mount));
      std::mt19937_64 rng(static_cast<std::uint64_t>(seed));
      std::normal_distribution<double> tilt(0.0, 0.02);
      std::vector<UrgRawScan> raw_scans;
      for (int k = 0; k < 8; ++k) raw_scans.push_back(floor_scan(urg, mount, rng));
      PlanarBeams beams;
      std::vector<MapPoint> points;
      TrunkPose pose;
      pose.x_m = start_x_m;
      for (int k = 0; k < scans; ++k) {
        UrgRawScan& raw = raw_scans[static_cast<std::size_t>(k) % raw_scans.size()];
        pose.x_m += 0.003;
        pose.yaw_rad += 0.002;
        pose.pitch_rad = tilt(rng);
        pose.roll_rad = tilt(rng);
        raw.time_s = 0.1 * (k + 1);
        model.to_beams(raw, beams);
        const PlanarBeamGeometry geometry(pose, mount);
        const Eigen::Vector3d origin = sensor_origin_in_map(pose, mount);
        for (std::size_t v = 0; v < 3; ++v) {
          const MaxElevationChange bound(others[v].motion_to(pose), geometry.gamma_rad, mount, options.update,
                                         pose.yaw_rad);
          points.clear();
          for (std::size_t i = 0; i < beams.count; ++i) {
            const double r = beams.range_m[i], dr = beams.range_error_m[i];
            const double ct = beams.cos_angle[i], st = beams.sin_angle[i];
            points.push_back(variants[v] == Variant::double_harness
                                 ? map_point<double>(geometry, bound, options.update, origin, r, dr, ct, st, true)
                                 : map_point<float>(geometry, bound, options.update, origin, r, dr, ct, st,
                                                    variants[v] == Variant::all_float));
          }
          others[v].integrate_points(points, pose, raw.time_s);
        }
        packed.integrate(beams, pose);
        for (std::size_t v = 0; v < 3; ++v) compare(packed.map(), others[v].map(), totals[v]);
      }
    }
    for (std::size_t v = 0; v < 3; ++v) {
      const Difference& d = totals[v];
      std::printf("start_x_m %6.0f  %-7s  cells_compared %zu  elevation_differs %zu (%.3f)  largest_m %.3g  "
                  "known_in_one %zu  state_or_certainty_differs %zu (%.1e)\n",
                  start_x_m, names[v], d.compared, d.elevation_differs,
                  static_cast<double>(d.elevation_differs) / static_cast<double>(d.compared), d.largest_m,
                  d.known_in_one, d.state_or_certainty_differs,
                  static_cast<double>(d.state_or_certainty_differs) / static_cast<double>(d.compared));
      // The double harness must be the library's path, or the float rows mean nothing.
      if (variants[v] == Variant::double_harness &&
          (d.elevation_differs != 0 || d.known_in_one != 0 || d.state_or_certainty_differs != 0)) {
        std::fprintf(stderr, "float_path_check: the double harness differs from the library's path\n");
        status = 1;
      }
    }
  }
  return status;
}
