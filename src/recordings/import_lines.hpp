#pragma once
// Internal to the importers (recordings/log_import.hpp): cutting text into lines
// and fields, reading numbers strictly, and turning ranges into the scan
// log's raw values.
#include <charconv>
#include <cmath>
#include <cstdint>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

#include "stridemap/recordings/log_import.hpp"

namespace stridemap::io::detail {

/// Calls use(line, number) for every line, without its LF or CR, telling
/// `progress` the kilobytes read of the whole now and then.
template <typename Use>
void for_each_line(std::string_view text, Use&& use, const ProgressCallback& progress = {}) {
  constexpr std::size_t kLinesPerReport = 4096;
  const std::size_t total_kb = text.size() / 1024;
  const std::size_t size = text.size();
  std::size_t number = 0;
  while (!text.empty()) {
    const std::size_t lf = text.find('\n');
    std::string_view line = text.substr(0, lf);
    text = lf == std::string_view::npos ? std::string_view{} : text.substr(lf + 1);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    use(line, ++number);
    if (progress && number % kLinesPerReport == 0) progress((size - text.size()) / 1024, total_kb);
  }
  if (progress) progress(total_kb, total_kb);
}

/// Fields separated by spaces and tabs (and commas with `commas`).
inline std::vector<std::string_view> split_fields(std::string_view line, bool commas = false) {
  std::vector<std::string_view> fields;
  std::size_t start = 0;
  const auto separator = [commas](char c) { return c == ' ' || c == '\t' || (commas && c == ','); };
  for (std::size_t k = 0; k <= line.size(); ++k) {
    if (k == line.size() || separator(line[k])) {
      if (k > start) fields.push_back(line.substr(start, k - start));
      start = k + 1;
    }
  }
  return fields;
}

/// A whole field as a number; doubles must be finite.
template <typename T>
bool parse_number(std::string_view field, T& out) {
  if (!field.empty() && field.front() == '+') field.remove_prefix(1);
  const auto [end, error] = std::from_chars(field.data(), field.data() + field.size(), out);
  if (error != std::errc() || end != field.data() + field.size()) return false;
  if constexpr (std::is_floating_point_v<T>) return std::isfinite(out);
  return true;
}

/// Records a malformed line: counted, and its message kept (up to a limit).
inline void skip_line(ImportReport& report, const std::string& source, std::size_t line, const std::string& what) {
  ++report.skipped;
  if (report.problems.size() < kMaxImportProblems) {
    report.problems.push_back(source + ":" + std::to_string(line) + ": " + what);
  }
}

/// The largest value a scan log holds (SCIP's 3-character encoding).
inline constexpr std::uint32_t kLargestRawValue = (1u << 18) - 1;

/// A range in metres as a raw URG value in millimetres; no return (NaN,
/// zero, negative) becomes 0, below every DMIN, i.e. an error code.
inline std::uint32_t range_to_raw_mm(double range_m) {
  if (!(range_m > 0.0)) return 0;
  const double mm = std::round(range_m * 1000.0);
  return mm >= kLargestRawValue ? kLargestRawValue : static_cast<std::uint32_t>(mm);
}

/// A range against the sensor's limits: at or beyond `max_range_m` it is
/// "no return" of a scanner that reports its maximum then, and is stored
/// above DMAX so that the sensor model counts it as beyond the range.
inline std::uint32_t limited_range_to_raw_mm(double range_m, double max_range_m, int max_distance_mm) {
  if (range_m >= max_range_m) {
    const auto above = static_cast<std::uint32_t>(max_distance_mm) + 1;
    return above > kLargestRawValue ? kLargestRawValue : above;
  }
  return range_to_raw_mm(range_m);
}

/// A scan as the scan log stores it, on one clock for host and sensor.
inline UrgScan make_scan(std::size_t index, double time_s, double first_time_s, int first_step, int cluster,
                         std::vector<std::uint32_t> values_mm) {
  UrgScan scan;
  scan.sequence = index;
  scan.host_time_s = time_s;
  scan.host_receive_time_s = time_s;
  const double since_ms = std::round((time_s - first_time_s) * 1000.0);
  scan.sensor_time_ms = since_ms > 0 ? static_cast<std::uint64_t>(since_ms) : 0;
  scan.sensor_timestamp_ms = static_cast<std::uint32_t>(scan.sensor_time_ms & 0xFFFFFFu);
  scan.first_after_start = index == 0;
  scan.raw.time_s = time_s;
  scan.raw.first_step = first_step;
  scan.raw.cluster = cluster;
  scan.raw.values_mm = std::move(values_mm);
  return scan;
}

/// A beam layout in URG steps (sensor_for_beams): the PP block and where a
/// scan's values start.
struct BeamSteps {
  scip::ScipParameters sensor;
  int first_step = 0;
  int cluster = 1;
};

BeamSteps beam_steps(double angle_min_rad, double angle_step_rad, std::size_t count, double min_range_m,
                     double max_range_m, const std::string& source);

scip::VersionInfo imported_version(const std::string& format);

}  // namespace stridemap::io::detail
