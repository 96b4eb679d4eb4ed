#pragma once
// Internal to the importers (recordings/log_import.hpp): cutting text into lines
// and fields, reading numbers strictly, and turning ranges into the scan
// log's raw values.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

#include "stridemap/core/error.hpp"
#include "stridemap/recordings/log_import.hpp"

namespace stridemap::io::detail {

/// Bytes searched for a NUL before a text is taken as text: enough to
/// hold a few lines of any of the formats.
inline constexpr std::size_t kTextSniffBytes = 4096;

/// The text with a UTF-8 byte order mark removed (editors on Windows add
/// one; left in, it would glue itself to the first field). Throws
/// InputError when the first kTextSniffBytes hold a NUL: binary data or
/// UTF-16, which would otherwise come out as thousands of malformed lines.
inline std::string_view text_body(std::string_view text, const std::string& source) {
  const std::string_view head = text.substr(0, kTextSniffBytes);
  if (head.starts_with("\xFF\xFE") || head.starts_with("\xFE\xFF")) {
    throw InputError(source + ": UTF-16 text; save it as UTF-8 (or plain ASCII) to import it");
  }
  if (const std::size_t nul = head.find('\0'); nul != std::string_view::npos) {
    throw InputError(source + ": not a text file (a NUL byte at offset " + std::to_string(nul) + ")");
  }
  if (text.starts_with("\xEF\xBB\xBF")) text.remove_prefix(3);
  return text;
}

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

/// A time as it was written, in the fewest digits that read back the same.
inline std::string time_text(double time) {
  char buffer[32];
  const auto end = std::to_chars(buffer, buffer + sizeof buffer, time).ptr;
  return std::string(buffer, end);
}
inline std::string time_text(std::uint64_t time) { return std::to_string(time); }

/// Which of `times` to keep so that the kept ones increase strictly: the
/// longest such subsequence, and of several equally long the one with the
/// earliest records. Rejecting each record not later than the last kept
/// one instead lets one far-future time (1e308) reject every record after
/// it; the longest subsequence costs that one record only. O(n log n).
template <typename T>
std::vector<bool> longest_increasing_times(const std::vector<T>& times) {
  const std::size_t n = times.size();
  // from_here[i]: the length of the longest increasing subsequence
  // starting at i, found right to left. heads[k]: the largest start time
  // of such a subsequence of length k + 1 seen so far, decreasing in k.
  std::vector<std::size_t> from_here(n);
  std::vector<T> heads;
  for (std::size_t i = n; i-- > 0;) {
    const auto at = std::lower_bound(heads.begin(), heads.end(), times[i], std::greater<T>());
    from_here[i] = static_cast<std::size_t>(at - heads.begin()) + 1;
    if (at == heads.end()) {
      heads.push_back(times[i]);
    } else {
      *at = times[i];
    }
  }
  // Forwards, the first record that still starts a long enough
  // subsequence after the last kept one is the earliest choice.
  std::vector<bool> keep(n, false);
  std::size_t needed = heads.size();
  bool any = false;
  T last{};
  for (std::size_t i = 0; i < n && needed > 0; ++i) {
    if (from_here[i] == needed && (!any || times[i] > last)) {
      keep[i] = true;
      last = times[i];
      any = true;
      --needed;
    }
  }
  return keep;
}

/// Keeps the records of longest_increasing_times (`time` and `line` are
/// the members holding a record's time and line number); each other is
/// counted as skipped and out of order, and named with the kept records
/// around it. `unit` follows each time in the messages (" us").
template <typename Record, typename T>
std::vector<Record> keep_increasing_times(std::vector<Record> records, T Record::*time, ImportReport& report,
                                          const std::string& source, const std::string& unit = "") {
  std::vector<T> times(records.size());
  for (std::size_t k = 0; k < records.size(); ++k) times[k] = records[k].*time;
  const std::vector<bool> keep = longest_increasing_times(times);
  const std::size_t none = std::numeric_limits<std::size_t>::max();
  std::vector<std::size_t> next_kept(records.size(), none);
  for (std::size_t k = records.size(), next = none; k-- > 0;) {
    next_kept[k] = next;
    if (keep[k]) next = k;
  }
  const auto named = [&](std::size_t k) {
    return "line " + std::to_string(records[k].line) + " (time " + time_text(times[k]) + unit + ")";
  };
  std::vector<std::pair<std::size_t, std::string>> problems;
  std::vector<Record> kept;
  kept.reserve(records.size());
  for (std::size_t k = 0, previous = none; k < records.size(); ++k) {
    if (keep[k]) {
      kept.push_back(std::move(records[k]));
      previous = k;
      continue;
    }
    ++report.skipped;
    ++report.out_of_order;
    if (problems.size() >= kMaxImportProblems) continue;
    const std::size_t next = next_kept[k];
    std::string what = "time " + time_text(times[k]) + unit;
    if (previous != none && times[previous] == times[k]) {
      what += " repeats line " + std::to_string(records[previous].line) + "'s";
    } else if (next != none && times[next] == times[k]) {
      what += " repeats line " + std::to_string(records[next].line) + "'s";
    } else {
      what += " is out of order: ";
      if (previous != none && next != none) {
        what += "the records kept around it are " + named(previous) + " and " + named(next);
      } else if (previous != none) {
        what += "the last record kept is " + named(previous);
      } else if (next != none) {
        what += "the first record kept is " + named(next);
      }
    }
    what += "; the import keeps the most records whose times increase down the file";
    problems.emplace_back(records[k].line, source + ":" + std::to_string(records[k].line) + ": " + what);
  }
  // Both lists are in line order and each holds its first
  // kMaxImportProblems; merged, the report's stay the first by line. The
  // report's messages begin "<source>:<line>:".
  const auto line_of = [&](const std::string& message) {
    std::size_t line = 0;
    const char* begin = message.data() + std::min(message.size(), source.size() + 1);
    std::from_chars(begin, message.data() + message.size(), line);
    return line;
  };
  std::vector<std::string> merged;
  merged.reserve(std::min(kMaxImportProblems, report.problems.size() + problems.size()));
  auto a = report.problems.begin();
  auto b = problems.begin();
  while (merged.size() < kMaxImportProblems && (a != report.problems.end() || b != problems.end())) {
    if (b == problems.end() || (a != report.problems.end() && line_of(*a) < b->first)) {
      merged.push_back(std::move(*a++));
    } else {
      merged.push_back(std::move(b->second));
      ++b;
    }
  }
  report.problems = std::move(merged);
  return kept;
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
  // Clamped: a time far beyond the others (1e308 s) must not overflow the cast.
  const double since_ms = std::min(std::round((time_s - first_time_s) * 1000.0), 1.8e19);
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
