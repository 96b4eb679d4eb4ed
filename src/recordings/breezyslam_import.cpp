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

  // Kept in file order until every time is known: which times are out of
  // order depends on all of them, and the dead reckoning runs over the
  // kept scans only.
  struct Record {
    std::size_t line = 0;
    std::uint64_t time_us = 0;
    std::int64_t left = 0, right = 0;
    std::vector<std::uint32_t> values;
  };
  std::vector<Record> records;
  detail::for_each_line(detail::text_body(text, source), [&](std::string_view line, std::size_t number) {
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
    Record record;
    record.line = number;
    if (!detail::parse_number(fields[0], record.time_us)) {
      return skip("time '" + std::string(fields[0]) + "' is not a whole number of microseconds");
    }
    if (!detail::parse_number(fields[2], record.left) || !detail::parse_number(fields[3], record.right)) {
      return skip("wheel ticks (fields 3 and 4) are not whole numbers");
    }
    record.values.resize(options.values_per_scan);
    for (std::size_t k = 0; k < record.values.size(); ++k) {
      if (!detail::parse_number(fields[24 + k], record.values[k]) || record.values[k] > detail::kLargestRawValue) {
        return skip("range " + std::to_string(k + 1) + " ('" + std::string(fields[24 + k]) +
                    "') is not a whole number of millimetres up to " + std::to_string(detail::kLargestRawValue));
      }
    }
    records.push_back(std::move(record));
  }, options.progress);
  records = detail::keep_increasing_times(std::move(records), &Record::time_us, out.report, source, " us");

  TimedPose pose;  // dead reckoning from (0, 0), heading +X
  out.scans.reserve(records.size());
  out.poses.reserve(records.size());
  for (std::size_t k = 0; k < records.size(); ++k) {
    Record& record = records[k];
    if (k > 0) {
      // Differential drive: the wheels' arcs give the travel and the turn;
      // the travel is taken along the mean heading of the step.
      const double left_m = static_cast<double>(record.left - records[k - 1].left) * metres_per_tick;
      const double right_m = static_cast<double>(record.right - records[k - 1].right) * metres_per_tick;
      const double travel = 0.5 * (left_m + right_m);
      const double turn = (right_m - left_m) / (2.0 * options.half_axle_length_m);
      const double heading = pose.pose.yaw_rad + 0.5 * turn;
      pose.pose.x_m += travel * std::cos(heading);
      pose.pose.y_m += travel * std::sin(heading);
      pose.pose.yaw_rad = std::remainder(pose.pose.yaw_rad + turn, 2.0 * std::numbers::pi);
    }
    const double time_s = static_cast<double>(record.time_us) * 1e-6;
    pose.time_s = time_s;
    out.scans.push_back(detail::make_scan(out.scans.size(), time_s, static_cast<double>(records.front().time_us) * 1e-6,
                                          options.first_step, 1, std::move(record.values)));
    out.poses.push_back(pose);
  }
  out.report.scans = out.scans.size();
  out.report.poses = out.poses.size();
  return out;
}

}  // namespace stridemap::io
