#pragma once
// A recorded run for the tool's tests of where the window goes: a robot
// moving along x at a known position, every beam reading the same range, so
// the points form a band around the path. Written as `stridemap map --log`
// reads it (a scan log and a pose file).
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <functional>
#include <string>

#include "cli/cli_runner.hpp"
#include "live/test_folder.hpp"
#include "stridemap/recordings/scan_log.hpp"

namespace stridemap::test {

inline constexpr double kStraightRunStart_s = 1733065200.0;

// `scans` scans at 10 Hz into dir/log_name, every one of the 682 beams at
// `range_mm`; dir/poses.txt at 20 Hz, from 0.1 s before the first scan to
// 0.1 s after the last, with x from `x_m_at(seconds since the start)`.
inline void write_straight_run(const TestFolder& dir, const std::string& log_name, int scans,
                               std::uint32_t range_mm, const std::function<double(double)>& x_m_at) {
  {
    io::ScanLogWriter writer(dir / log_name, "/dev/ttyACM0");
    const scip::VersionInfo version{"Hokuyo Automatic Co.,Ltd.", "SOKUIKI Sensor URG-04LX", "3.3.00", "SCIP 2.0", "H0"};
    writer.write_sensor(kStraightRunStart_s, version, scip::ScipParameters{});
    for (int k = 0; k < scans; ++k) {
      UrgScan s;
      s.sequence = static_cast<std::uint64_t>(k);
      s.sensor_time_ms = static_cast<std::uint64_t>(100 * k);
      s.sensor_timestamp_ms = static_cast<std::uint32_t>(100 * k);
      s.host_time_s = kStraightRunStart_s + 0.1 * k;
      s.host_receive_time_s = s.host_time_s + 0.1;
      s.raw.time_s = s.host_time_s;
      s.raw.values_mm.assign(682, range_mm);
      writer.write_scan(s);
    }
  }
  std::ofstream poses(dir / "poses.txt");
  for (int k = -2; k <= 2 * scans + 2; ++k) {
    const double t = 0.05 * k;
    char line[128];
    std::snprintf(line, sizeof line, "%.3f %.4f 0 0 0 0\n", kStraightRunStart_s + t, x_m_at(t));
    poses << line;
  }
}

// `stridemap map` over that run into dir/out, with `extra` options.
inline CommandResult map_straight_run(const TestFolder& dir, const std::string& log_name, const std::string& out,
                                      const std::string& extra) {
  return run_cli("map --log " + shell_quoted(dir / log_name) + " --poses " + shell_quoted(dir / "poses.txt") +
                 " --out " + shell_quoted(dir / out) + " " + extra);
}

}  // namespace stridemap::test
