#include "stridemap/recordings/recorded_scans.hpp"

#include <cerrno>
#include <charconv>
#include <cstring>
#include <fstream>
#include <iterator>
#include <string_view>

#include "stridemap/core/error.hpp"
#include "stridemap/recordings/scan_log.hpp"
#include "stridemap/sensors/scip_encoding.hpp"
#include "stridemap/io/text_file.hpp"

namespace stridemap::io {
namespace {

std::string read_recording(const std::string& path) {
  refuse_folder(path, "the recording");
  std::ifstream file(path, std::ios::binary);
  if (!file) throw InputError(path + ": cannot open the recording: " + std::strerror(errno));
  std::string content{std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>()};
  if (file.bad()) throw InputError(path + ": cannot read the recording: " + std::strerror(errno));
  return content;
}

// The emulator sends the values in SCIP's 3-character encoding (18 bits).
const std::uint32_t kLargestRecordedValue = scip::max_encodable_value(3);

bool is_blank(char c) { return c == ' ' || c == '\t' || c == '\r'; }

}  // namespace

RecordedScans parse_breezyslam_scans(std::string_view text, const std::string& source_name,
                                     std::size_t values_per_scan) {
  constexpr std::size_t kFirstValueToken = 24;
  RecordedScans out;
  out.format = "breezyslam";
  std::size_t number = 0, line_start = 0;
  while (line_start < text.size()) {
    ++number;
    std::size_t line_end = text.find('\n', line_start);
    if (line_end == std::string_view::npos) line_end = text.size();
    const std::string_view line = text.substr(line_start, line_end - line_start);
    line_start = line_end + 1;
    std::vector<std::uint32_t>& values = out.scans.emplace_back();
    values.reserve(values_per_scan);
    std::size_t token = 0, pos = 0;
    while (true) {
      while (pos < line.size() && is_blank(line[pos])) ++pos;
      if (pos >= line.size()) break;
      std::size_t end = pos;
      while (end < line.size() && !is_blank(line[end])) ++end;
      if (token >= kFirstValueToken) {
        std::uint32_t v = 0;
        const auto [stop, error] = std::from_chars(line.data() + pos, line.data() + end, v);
        if (error != std::errc() || stop != line.data() + end || v > kLargestRecordedValue) {
          throw InputError(source_name + ":" + std::to_string(number) + ": token " + std::to_string(token + 1) + " '" +
                           std::string(line.substr(pos, end - pos)) +
                           "' is not a raw URG value (a whole number of mm, at most " + std::to_string(kLargestRecordedValue) +
                           ", what SCIP's 3 characters hold)");
        }
        // A line longer than a scan is an error whatever follows; stopping
        // here keeps a huge line from growing the scan without bound.
        if (values.size() == values_per_scan) {
          throw InputError(source_name + ":" + std::to_string(number) + ": more than " +
                           std::to_string(kFirstValueToken + values_per_scan) + " tokens; a BreezySLAM scan line has " +
                           std::to_string(kFirstValueToken + values_per_scan) + " (24 fields, then " +
                           std::to_string(values_per_scan) + " values)");
        }
        values.push_back(v);
      }
      ++token;
      pos = end;
    }
    if (token == 0) {
      out.scans.pop_back();  // blank line
      continue;
    }
    if (values.size() != values_per_scan) {
      throw InputError(source_name + ":" + std::to_string(number) + ": " + std::to_string(token) +
                       " tokens; a BreezySLAM scan line has " + std::to_string(kFirstValueToken + values_per_scan) +
                       " (24 fields, then " + std::to_string(values_per_scan) + " values)");
    }
  }
  if (out.scans.empty()) throw InputError(source_name + ": no scans in the recording");
  return out;
}

RecordedScans read_breezyslam_scans(const std::string& path, std::size_t values_per_scan) {
  return parse_breezyslam_scans(read_recording(path), path, values_per_scan);
}

RecordedScans parse_recorded_scans(std::string_view text, const std::string& source_name) {
  if (text.substr(0, 17) != "stridemap-urg-log") return parse_breezyslam_scans(text, source_name);
  const ScanLog log = parse_scan_log(text, source_name);
  RecordedScans out;
  out.format = "stridemap";
  if (log.scans.empty()) {
    throw InputError(source_name + ": no scans in the log" + (log.damage.empty() ? "" : " (" + log.damage + ")"));
  }
  out.first_step = log.scans.front().raw.first_step;
  out.cluster = log.scans.front().raw.cluster;
  for (const UrgScan& s : log.scans) {
    if (s.raw.first_step != out.first_step || s.raw.cluster != out.cluster) {
      throw InputError(source_name + ": scan " + std::to_string(s.sequence) +
                       " has other steps or cluster than the first; replay needs one layout");
    }
    out.scans.push_back(s.raw.values_mm);
  }
  return out;
}

RecordedScans read_recorded_scans(const std::string& path) { return parse_recorded_scans(read_recording(path), path); }

}  // namespace stridemap::io
