// Minimal use of the library from a robot's code: raw URG-04LX values in,
// elevation and certainty out, through the mapping pipeline. The scan here
// is synthetic (flat floor seen by the paper's Messor mount); on a robot it
// comes from the driver.
#include <cmath>
#include <cstdio>

#include <stridemap/pipeline/mapping_pipeline.hpp>

int main() {
  stridemap::PipelineOptions options;  // URG-04LX defaults, 0.26 m high, pitched 35 deg down
  options.mapper.window_ahead_m = 0.3;  // keep the stripe ahead of the robot inside the map
  stridemap::MappingPipeline pipeline(options);
  const stridemap::UrgParameters& urg = options.urg;
  const stridemap::SensorMount& mount = options.mount;

  stridemap::UrgRawScan raw;
  for (int k = 0; k < 40; ++k) {
    stridemap::TrunkPose pose;
    pose.x_m = 0.01 * k;  // walking forward 10 mm per scan
    raw.time_s = 0.1 * k;  // the URG-04LX scans at 10 Hz; the mapper rejects scans that are not newer
    raw.values_mm.clear();
    for (int step = urg.first_step; step <= urg.last_step; ++step) {
      const double t = urg.step_angle_rad(step);
      const double down = std::cos(t) * std::sin(mount.pitch_rad);  // downward part of the unit beam
      const double range_m = down > 0.05 ? mount.height_m / down : 0.0;
      raw.values_mm.push_back(range_m > 0.0 && range_m < 4.0 ? static_cast<unsigned>(range_m * 1000.0) : 0u);
    }
    pipeline.add(raw, pose);
  }
  pipeline.finish();
  const stridemap::ElevationMap map = pipeline.filtered_map();  // fill-in (eq. 11) on a copy

  const stridemap::CellIndex ahead = map.cell_of(0.39 + 0.37, 0.0);
  std::printf("cell 0.37 m ahead of the last pose: elevation %.4f m, certainty %.0f\n",
              map.elevation(ahead), map.certainty(ahead));
  return std::abs(map.elevation(ahead)) < 0.002 && map.certainty(ahead) > 0 ? 0 : 1;
}
