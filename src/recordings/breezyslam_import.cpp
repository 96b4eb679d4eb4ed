#include <cmath>
#include <numbers>

#include "import_lines.hpp"
#include "stridemap/core/error.hpp"
#include "stridemap/recordings/log_import.hpp"

namespace stridemap::io {

ImportedData import_breezyslam(std::string_view text, const std::string& source,
                               const BreezySlamImportOptions& options) {
  if (!(options.wheel_radius_m > 0.0) || !(options.half_axle_length_m > 0.0) ||
      !(options.ticks_per_revolution > 0.0) || options.values_per_scan == 0 || options.first_step < 0) {
    throw InputError(source + ": BreezySLAM import: wheel radius, half axle length, ticks per revolution and "
                              "values per scan must be positive, the first step not negative");
  }
  ImportedData out;
  out.format = "breezyslam";
  out.version = detail::imported_version("BreezySLAM");
  // The URG-04LX's own PP, widened when the log holds more values than
  // AMIN..AMAX (the published logs: 683 values from step 44, one past AMAX).
  out.sensor.last_step = std::max(out.sensor.last_step,
                                  options.first_step + static_cast<int>(options.values_per_scan) - 1);
  if (out.sensor.first_step > options.first_step) out.sensor.first_step = options.first_step;
  if (out.sensor.last_step >= out.sensor.steps_per_turn) {
    throw InputError(source + ": " + std::to_string(options.values_per_scan) + " values from step " +
                     std::to_string(options.first_step) + " do not fit the URG-04LX's " +
                     std::to_string(out.sensor.steps_per_turn) + " steps");
  }
  const std::size_t expected = 24 + options.values_per_scan;
  const double metres_per_tick = 2.0 * std::numbers::pi * options.wheel_radius_m / options.ticks_per_revolution;

  TimedPose pose;  // dead reckoning from (0, 0), heading +X
  std::int64_t previous_left = 0, previous_right = 0;
  std::uint64_t previous_us = 0;
  double first_time_s = 0.0;
  detail::for_each_line(text, [&](std::string_view line, std::size_t number) {
    ++out.report.lines;
    const auto fields = detail::split_fields(line);
    if (fields.empty() || fields.front().front() == '#') {
      ++out.report.ignored;
      return;
    }
    const auto skip = [&](const std::string& what) { detail::skip_line(out.report, source, number, what); };
    if (fields.size() != expected) {
      skip(std::to_string(fields.size()) + " fields, expected " + std::to_string(expected) +
           " (time, 23 robot fields, " + std::to_string(options.values_per_scan) + " ranges)");
      return;
    }
    std::uint64_t time_us = 0;
    std::int64_t left = 0, right = 0;
    if (!detail::parse_number(fields[0], time_us)) return skip("time '" + std::string(fields[0]) + "' is not a whole number of microseconds");
    if (!detail::parse_number(fields[2], left) || !detail::parse_number(fields[3], right)) {
      return skip("wheel ticks (fields 3 and 4) are not whole numbers");
    }
    std::vector<std::uint32_t> values(options.values_per_scan);
    for (std::size_t k = 0; k < values.size(); ++k) {
      if (!detail::parse_number(fields[24 + k], values[k]) || values[k] > detail::kLargestRawValue) {
        return skip("range " + std::to_string(k + 1) + " ('" + std::string(fields[24 + k]) +
                    "') is not a whole number of millimetres up to " + std::to_string(detail::kLargestRawValue));
      }
    }
    if (!out.scans.empty() && time_us <= previous_us) {
      return skip("time " + std::to_string(time_us) + " us is not later than the previous scan's " +
                  std::to_string(previous_us) + " us");
    }
    const double time_s = static_cast<double>(time_us) * 1e-6;
    if (out.scans.empty()) {
      first_time_s = time_s;
    } else {
      // Differential drive: the wheels' arcs give the travel and the turn;
      // the travel is taken along the mean heading of the step.
      const double left_m = static_cast<double>(left - previous_left) * metres_per_tick;
      const double right_m = static_cast<double>(right - previous_right) * metres_per_tick;
      const double travel = 0.5 * (left_m + right_m);
      const double turn = (right_m - left_m) / (2.0 * options.half_axle_length_m);
      const double heading = pose.pose.yaw_rad + 0.5 * turn;
      pose.pose.x_m += travel * std::cos(heading);
      pose.pose.y_m += travel * std::sin(heading);
      pose.pose.yaw_rad = std::remainder(pose.pose.yaw_rad + turn, 2.0 * std::numbers::pi);
    }
    previous_left = left;
    previous_right = right;
    previous_us = time_us;
    pose.time_s = time_s;
    out.scans.push_back(detail::make_scan(out.scans.size(), time_s, first_time_s, options.first_step, 1,
                                          std::move(values)));
    out.poses.push_back(pose);
  }, options.progress);
  out.report.scans = out.scans.size();
  out.report.poses = out.poses.size();
  return out;
}

}  // namespace stridemap::io
