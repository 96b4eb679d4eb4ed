#include "stridemap/io/recorded_scans.hpp"

#include <cerrno>
#include <charconv>
#include <cstring>
#include <fstream>
#include <string_view>

#include "stridemap/core/error.hpp"
#include "stridemap/io/scan_log.hpp"

namespace stridemap::io {

RecordedScans read_breezyslam_scans(const std::string& path, std::size_t values_per_scan) {
  constexpr std::size_t kFirstValueToken = 24;
  std::ifstream file(path);
  if (!file) throw InputError(path + ": cannot open the recording: " + std::strerror(errno));
  RecordedScans out;
  out.format = "breezyslam";
  std::string line;
  std::size_t number = 0;
  while (std::getline(file, line)) {
    ++number;
    std::vector<std::uint32_t>& values = out.scans.emplace_back();
    values.reserve(values_per_scan);
    std::size_t token = 0, pos = 0;
    while (true) {
      while (pos < line.size() && (line[pos] == ' ' || line[pos] == '\t' || line[pos] == '\r')) ++pos;
      if (pos >= line.size()) break;
      std::size_t end = pos;
      while (end < line.size() && line[end] != ' ' && line[end] != '\t' && line[end] != '\r') ++end;
      if (token >= kFirstValueToken) {
        std::uint32_t v = 0;
        const auto [stop, error] = std::from_chars(line.data() + pos, line.data() + end, v);
        if (error != std::errc() || stop != line.data() + end) {
          throw InputError(path + ":" + std::to_string(number) + ": token " + std::to_string(token + 1) + " '" +
                           line.substr(pos, end - pos) + "' is not a raw URG value (a whole number of mm)");
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
      throw InputError(path + ":" + std::to_string(number) + ": " + std::to_string(token) + " tokens; a BreezySLAM scan line has " +
                       std::to_string(kFirstValueToken + values_per_scan) + " (24 fields, then " +
                       std::to_string(values_per_scan) + " values)");
    }
  }
  if (out.scans.empty()) throw InputError(path + ": no scans in the recording");
  return out;
}

RecordedScans read_recorded_scans(const std::string& path) {
  std::ifstream file(path);
  if (!file) throw InputError(path + ": cannot open the recording: " + std::strerror(errno));
  std::string first;
  std::getline(file, first);
  if (std::string_view(first).substr(0, 17) != "stridemap-urg-log") return read_breezyslam_scans(path);
  const ScanLog log = read_scan_log(path);
  RecordedScans out;
  out.format = "stridemap";
  if (log.scans.empty()) throw InputError(path + ": no scans in the log" + (log.damage.empty() ? "" : " (" + log.damage + ")"));
  out.first_step = log.scans.front().raw.first_step;
  out.cluster = log.scans.front().raw.cluster;
  for (const UrgScan& s : log.scans) {
    if (s.raw.first_step != out.first_step || s.raw.cluster != out.cluster) {
      throw InputError(path + ": scan " + std::to_string(s.sequence) +
                       " has other steps or cluster than the first; replay needs one layout");
    }
    out.scans.push_back(s.raw.values_mm);
  }
  return out;
}

}  // namespace stridemap::io
