#include "stridemap/io/scan_log.hpp"

#include <zlib.h>

#include <cerrno>
#include <charconv>
#include <cstring>
#include <fstream>
#include <iterator>
#include <string_view>

#include "stridemap/core/error.hpp"
#include "stridemap/io/text_file.hpp"
#include "stridemap/sensors/scip_encoding.hpp"

namespace stridemap::io {
namespace {

constexpr std::string_view kMagic = "stridemap-urg-log";
constexpr std::size_t kMaxSkippedLinesListed = 20;
constexpr std::size_t kCrcSuffix = 10;  // " *" + 8 hex digits
// SCIP's 3-character encoding holds 18 bits: no sensor sends more.
const std::uint32_t kLargestValue = scip::max_encodable_value(3);

void append_number(double value, std::string& out) {
  char text[32];
  const auto [end, error] = std::to_chars(text, text + sizeof text, value);
  out.append(text, error == std::errc() ? end : text);
}

void append_number(std::uint64_t value, std::string& out) {
  char text[24];
  const auto [end, error] = std::to_chars(text, text + sizeof text, value);
  out.append(text, error == std::errc() ? end : text);
}

// Splits off space-separated fields from the front of `rest`.
class Fields {
 public:
  explicit Fields(std::string_view rest) : rest_(rest) {}
  bool next(std::string_view& field) {
    while (!rest_.empty() && rest_.front() == ' ') rest_.remove_prefix(1);
    if (rest_.empty()) return false;
    const std::size_t end = rest_.find(' ');
    field = rest_.substr(0, end);
    rest_ = end == std::string_view::npos ? std::string_view{} : rest_.substr(end);
    return true;
  }
  std::string_view rest() const {
    std::string_view r = rest_;
    if (!r.empty() && r.front() == ' ') r.remove_prefix(1);
    return r;
  }

 private:
  std::string_view rest_;
};

template <typename T>
bool read_number(Fields& fields, T& value) {
  std::string_view field;
  if (!fields.next(field)) return false;
  const auto [end, error] = std::from_chars(field.data(), field.data() + field.size(), value);
  return error == std::errc() && end == field.data() + field.size();
}

// Reads records one by one; each call returns an empty string or what is
// wrong with the record.
class LogParser {
 public:
  explicit LogParser(ScanLog& log) : log_(log) {}
  bool have_parameters() const { return have_parameters_; }

  bool in_block() const { return in_block_; }
  std::size_t block_line() const { return block_line_; }

  // A record; a sensor block open before it must have been closed first
  // unless the record belongs to it (vv/pp).
  std::string record(std::string_view body, std::size_t line) {
    Fields fields(body);
    std::string_view kind;
    if (!fields.next(kind)) return "empty record";
    if (kind == "vv" || kind == "pp") return info_line(kind, fields.rest());
    if (kind == "device") {
      log_.device = std::string(fields.rest());
      return {};
    }
    if (kind == "sensor") {
      double time = 0.0;
      if (!read_number(fields, time)) return "sensor: expected a host time";
      in_block_ = true;
      block_line_ = line;
      vv_.clear();
      pp_.clear();
      return {};
    }
    if (kind == "fault") return fault(fields);
    if (kind == "scan") return scan(fields);
    return "unknown record '" + std::string(kind) + "'";
  }

  // A sensor block ends at the first record that is not vv/pp (or at the end).
  std::string close_block() {
    if (!in_block_) return {};
    in_block_ = false;
    try {
      const scip::ScipParameters parameters = scip::parse_parameters(pp_);
      scip::to_urg_parameters(parameters).validate();
      if (have_parameters_ && !(parameters == log_.parameters)) {
        return "the sensor's parameters changed (another sensor?); the log is read up to here";
      }
      const scip::VersionInfo version = scip::parse_version(vv_);
      log_.parameters = parameters;
      log_.version = version;
      have_parameters_ = true;
      ++log_.connects;
    } catch (const InputError& e) {
      return e.what();
    }
    return {};
  }

 private:
  std::string info_line(std::string_view kind, std::string_view text) {
    if (!in_block_) {
      std::string problem(kind);
      problem += " line outside a sensor block";
      return problem;
    }
    const std::size_t colon = text.find(':');
    if (colon == std::string_view::npos || colon == 0) return "expected KEY:value after " + std::string(kind);
    (kind == "vv" ? vv_ : pp_).push_back({std::string(text.substr(0, colon)), std::string(text.substr(colon + 1))});
    return {};
  }

  std::string fault(Fields& fields) {
    LoggedFault f;
    std::string_view name;
    if (!read_number(fields, f.host_time_s) || !fields.next(name) || !read_number(fields, f.count)) {
      return "fault: expected host time, kind, count and message";
    }
    f.kind = std::string(name);
    f.message = std::string(fields.rest());
    log_.faults.push_back(std::move(f));
    return {};
  }

  std::string scan(Fields& fields) {
    if (!have_parameters_) return "a scan before the sensor's parameters (sensor/pp lines)";
    UrgScan s;
    int first_after = 0;
    std::size_t count = 0;
    if (!read_number(fields, s.sequence) || !read_number(fields, s.host_time_s) ||
        !read_number(fields, s.host_receive_time_s) || !read_number(fields, s.sensor_timestamp_ms) ||
        !read_number(fields, s.sensor_time_ms) || !read_number(fields, s.lost_before) ||
        !read_number(fields, first_after) || !read_number(fields, s.raw.first_step) ||
        !read_number(fields, s.raw.cluster) || !read_number(fields, count)) {
      return "scan: expected sequence, host time, receive time, sensor stamp, sensor time, lost, "
             "first-after-start, first step, cluster and value count";
    }
    if (count > 10000) return "scan: " + std::to_string(count) + " values is more than a URG sends";
    s.first_after_start = first_after != 0;
    s.raw.time_s = s.host_time_s;
    s.raw.values_mm.resize(count);
    for (std::size_t i = 0; i < count; ++i) {
      if (!read_number(fields, s.raw.values_mm[i])) {
        return "scan: value " + std::to_string(i + 1) + " is missing or not a whole number";
      }
      if (s.raw.values_mm[i] > kLargestValue) {
        return "scan: value " + std::to_string(i + 1) + " (" + std::to_string(s.raw.values_mm[i]) +
               ") is more than a URG can send (" + std::to_string(kLargestValue) + ")";
      }
    }
    std::string_view extra;
    if (fields.next(extra)) return "scan: more values than the count " + std::to_string(count);
    log_.scans.push_back(std::move(s));
    return {};
  }

  ScanLog& log_;
  bool have_parameters_ = false;
  bool in_block_ = false;
  std::size_t block_line_ = 0;
  std::vector<scip::InfoField> vv_, pp_;
};

}  // namespace

std::string scan_log_crc(std::string_view body) {
  const uLong crc = crc32(0L, reinterpret_cast<const Bytef*>(body.data()), static_cast<uInt>(body.size()));
  char text[12];
  std::snprintf(text, sizeof text, "%08lx", static_cast<unsigned long>(crc & 0xFFFFFFFFul));
  return text;
}

ScanLog read_scan_log(const std::string& path) {
  refuse_folder(path, "the scan log");
  std::ifstream file(path, std::ios::binary);
  if (!file) throw InputError(path + ": cannot open the scan log: " + std::strerror(errno));
  const std::string content{std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>()};
  if (file.bad()) throw InputError(path + ": cannot read the scan log: " + std::strerror(errno));
  return parse_scan_log(content, path);
}

// Each line carries its own CRC, so a damaged line (CRC, torn, a record
// that does not parse) is skipped and counted and reading goes on: one
// flipped byte loses one record. Damage inside a sensor block, or a block
// with other parameters, stops reading there: the scans after it would be
// read with the wrong sensor description. log.lines counts the lines before
// the first damage whose records are all kept: a sensor block counts once it
// is closed (by the next record or the end).
ScanLog parse_scan_log(std::string_view content, const std::string& source_name) {
  const std::string& path = source_name;
  ScanLog log;
  LogParser parser(log);
  std::size_t pos = 0, number = 0;
  bool stopped = false;
  const auto note_damage = [&](std::size_t line, const std::string& what) {
    const std::string place = path + ":" + std::to_string(line) + ": " + what;
    if (log.damage.empty()) log.damage = place;
    if (log.skipped.size() < kMaxSkippedLinesListed) log.skipped.push_back(place);
    log.skipped_line_numbers.push_back(line);
  };
  // Lines before the first damage, if the sensor block it interrupted closes well.
  std::size_t lines_if_block_closes = 0;
  const auto stop_at = [&](std::size_t line, const std::string& what) {
    stopped = true;
    std::string place = path + ":" + std::to_string(line) + ": " + what;
    if (!log.damage.empty()) place += "; the first damage: " + log.damage;
    if (!parser.have_parameters()) throw InputError(place + " (before the sensor's parameters: nothing usable)");
    log.stop = place;
    if (log.damage.empty()) log.damage = place;
  };
  // A line that cannot be used is skipped. Inside a sensor block the block
  // stays open: if its lines still describe the sensor when it closes (the
  // damaged line was a scan that came after it, or an empty line), all is
  // well; if not, reading stops at the block.
  const auto damaged_line = [&](const std::string& what) {
    if (parser.in_block() && log.damage.empty()) lines_if_block_closes = number - 1;
    note_damage(number, what);
  };
  const auto block_closed = [&] {
    if (lines_if_block_closes > 0) log.lines = lines_if_block_closes;
    lines_if_block_closes = 0;
  };
  while (pos < content.size() && !stopped) {
    ++number;
    const std::size_t lf = content.find('\n', pos);
    if (lf == std::string_view::npos) {
      damaged_line("truncated: the last line has no end (the recorder was stopped while writing it?)");
      break;
    }
    const std::string_view line = content.substr(pos, lf - pos);
    pos = lf + 1;
    if (line.size() < kCrcSuffix || line.compare(line.size() - kCrcSuffix, 2, " *") != 0) {
      if (number == 1) throw InputError(path + ":1: no CRC at the end of the line: not a stridemap scan log");
      damaged_line("no CRC at the end of the line");
      continue;
    }
    const std::string_view body = line.substr(0, line.size() - kCrcSuffix);
    if (scan_log_crc(body) != line.substr(line.size() - 8)) {
      if (number == 1) throw InputError(path + ":1: CRC mismatch on the first line: not a readable stridemap scan log");
      damaged_line("CRC mismatch: the line is corrupted");
      continue;
    }
    if (number == 1) {
      Fields fields(body);
      std::string_view magic;
      int version = 0;
      if (!fields.next(magic) || magic != kMagic || !read_number(fields, version)) {
        throw InputError(path + ": not a stridemap scan log (first line must be '" + std::string(kMagic) + " 1')");
      }
      if (version != kScanLogVersion) {
        throw InputError(path + ": scan log version " + std::to_string(version) + " is not supported (expected " +
                         std::to_string(kScanLogVersion) + ")");
      }
      log.lines = number;
      continue;
    }
    std::string_view kind;
    Fields(body).next(kind);
    const bool info_line = kind == "vv" || kind == "pp";
    if (!info_line && parser.in_block()) {
      if (const std::string problem = parser.close_block(); !problem.empty()) {
        stop_at(parser.block_line(), "sensor block: " + problem);
        break;
      }
      if (log.damage.empty()) log.lines = number - 1;
      block_closed();
    }
    if (kind == kMagic) {
      // `record --append` after a torn last line: the new part starts here.
      if (log.damage.empty()) log.lines = number;
      continue;
    }
    if (const std::string problem = parser.record(body, number); !problem.empty()) {
      damaged_line(problem);
      continue;
    }
    if (!parser.in_block() && log.damage.empty()) log.lines = number;
  }
  if (number == 0) throw InputError(path + ": empty file, not a scan log");
  if (!stopped && parser.in_block()) {
    if (const std::string problem = parser.close_block(); !problem.empty()) {
      stop_at(parser.block_line(), "sensor block: " + problem);
    } else if (log.damage.empty()) {
      log.lines = number;
    } else {
      block_closed();
    }
  }
  if (!parser.have_parameters()) {
    throw InputError(path + ": the log holds no sensor parameters (no complete sensor block)" +
                     (log.damage.empty() ? std::string() : "; the first damage: " + log.damage));
  }
  return log;
}

ScanLogWriter::ScanLogWriter(const std::string& path, const std::string& device, bool append) : path_(path) {
  file_ = std::fopen(path.c_str(), append ? "ab+" : "wb");
  if (file_ == nullptr) throw InputError(path + ": cannot create the scan log: " + std::strerror(errno));
  bool empty = true;
  if (append && std::fseek(file_, 0, SEEK_END) == 0 && std::ftell(file_) > 0) {
    empty = false;
    if (std::fseek(file_, -1, SEEK_END) == 0 && std::fgetc(file_) != '\n') {
      std::fseek(file_, 0, SEEK_END);
      std::fputc('\n', file_);
    }
    std::fseek(file_, 0, SEEK_END);
  }
  std::string body;
  if (empty) {
    body = std::string(kMagic) + " " + std::to_string(kScanLogVersion);
    write_line(body);
  }
  body = "device " + device;
  write_line(body);
  flush();
}

ScanLogWriter::~ScanLogWriter() {
  if (file_ != nullptr) std::fclose(file_);
}

void ScanLogWriter::write_line(std::string& body) {
  for (char& c : body) {
    if (c == '\n' || c == '\r') c = ' ';  // a record is one line, whatever a message holds
  }
  body += " *";
  body += scan_log_crc(body.substr(0, body.size() - 2));
  body += '\n';
  if (std::fwrite(body.data(), 1, body.size(), file_) != body.size()) failed_ = true;
}

void ScanLogWriter::write_sensor(double host_time_s, const scip::VersionInfo& version,
                                 const scip::ScipParameters& parameters) {
  line_ = "sensor ";
  append_number(host_time_s, line_);
  write_line(line_);
  for (const scip::InfoField& f : scip::to_info_fields(version)) {
    line_ = "vv " + f.key + ":" + f.value;
    write_line(line_);
  }
  for (const scip::InfoField& f : scip::to_info_fields(parameters)) {
    line_ = "pp " + f.key + ":" + f.value;
    write_line(line_);
  }
  flush();
}

void ScanLogWriter::write_scan(const UrgScan& s) {
  line_ = "scan ";
  append_number(s.sequence, line_);
  line_ += ' ';
  append_number(s.host_time_s, line_);
  line_ += ' ';
  append_number(s.host_receive_time_s, line_);
  for (const std::uint64_t v : {std::uint64_t{s.sensor_timestamp_ms}, s.sensor_time_ms, s.lost_before,
                                std::uint64_t{s.first_after_start ? 1u : 0u},
                                static_cast<std::uint64_t>(s.raw.first_step), static_cast<std::uint64_t>(s.raw.cluster),
                                std::uint64_t{s.raw.values_mm.size()}}) {
    line_ += ' ';
    append_number(v, line_);
  }
  for (const std::uint32_t v : s.raw.values_mm) {
    line_ += ' ';
    append_number(std::uint64_t{v}, line_);
  }
  write_line(line_);
  flush();
}

void ScanLogWriter::write_fault(double host_time_s, UrgFault fault, std::uint64_t count, const std::string& message) {
  line_ = "fault ";
  append_number(host_time_s, line_);
  line_ += ' ';
  line_ += fault_name(fault);
  line_ += ' ';
  append_number(count, line_);
  line_ += ' ';
  line_ += message;
  write_line(line_);
  flush();
}

void ScanLogWriter::flush() {
  if (std::fflush(file_) != 0) failed_ = true;
  if (failed_) throw InputError(path_ + ": cannot write the scan log (disk full?)");
}

}  // namespace stridemap::io
