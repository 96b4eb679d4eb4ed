#include "stridemap/recordings/scan_log.hpp"

#include <zlib.h>

#include <cerrno>
#include <charconv>
#include <cstdlib>
#include <cstring>
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
  // A scan record is read into `scan` (its storage reused) and sets `scan_ready`.
  LogParser(ScanLog& log, UrgScan& scan, bool& scan_ready) : log_(log), scan_(scan), scan_ready_(scan_ready) {}
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
    UrgScan& s = scan_;
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
    scan_ready_ = true;
    return {};
  }

  ScanLog& log_;
  UrgScan& scan_;
  bool& scan_ready_;
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

// Each line carries its own CRC, so a damaged line (CRC, torn, a record
// that does not parse) is skipped and counted and reading goes on: one
// flipped byte loses one record. Damage inside a sensor block, or a block
// with other parameters, stops reading there: the scans after it would be
// read with the wrong sensor description. log.lines counts the lines before
// the first damage whose records are all kept: a sensor block counts once it
// is closed (by the next record or the end). One line is held at a time
// (getline's buffer, reused), and one scan.
struct ScanLogReader::State {
  State(std::string source) : path(std::move(source)), parser(log, scan, scan_ready) {}
  ~State() {
    if (file != nullptr) std::fclose(file);
    std::free(line_buffer);
  }

  // The next line without its LF; `ended` false when it had none (the last, torn).
  bool read_line(std::string_view& line, bool& ended) {
    if (file == nullptr) {
      if (pos >= content.size()) return false;
      const std::size_t lf = content.find('\n', pos);
      ended = lf != std::string_view::npos;
      line = content.substr(pos, ended ? lf - pos : std::string_view::npos);
      pos = ended ? lf + 1 : content.size();
      return true;
    }
    errno = 0;
    const ssize_t got = ::getline(&line_buffer, &line_capacity, file);
    if (got < 0) {
      if (std::ferror(file)) throw InputError(path + ": cannot read the scan log: " + std::strerror(errno));
      return false;
    }
    line = std::string_view(line_buffer, static_cast<std::size_t>(got));
    ended = !line.empty() && line.back() == '\n';
    if (ended) line.remove_suffix(1);
    return true;
  }

  void note_damage(std::size_t line, const std::string& what) {
    const std::string place = path + ":" + std::to_string(line) + ": " + what;
    if (log.damage.empty()) log.damage = place;
    if (log.skipped.size() < kMaxSkippedLinesListed) log.skipped.push_back(place);
    log.skipped_line_numbers.push_back(line);
  }
  void stop_at(std::size_t line, const std::string& what) {
    stopped = true;
    std::string place = path + ":" + std::to_string(line) + ": " + what;
    if (!log.damage.empty()) place += "; the first damage: " + log.damage;
    if (!parser.have_parameters()) throw InputError(place + " (before the sensor's parameters: nothing usable)");
    log.stop = place;
    if (log.damage.empty()) log.damage = place;
  }
  // A line that cannot be used is skipped. Inside a sensor block the block
  // stays open: if its lines still describe the sensor when it closes (the
  // damaged line was a scan that came after it, or an empty line), all is
  // well; if not, reading stops at the block.
  void damaged_line(const std::string& what) {
    if (parser.in_block() && log.damage.empty()) lines_if_block_closes = number - 1;
    note_damage(number, what);
  }
  void block_closed() {
    if (lines_if_block_closes > 0) log.lines = lines_if_block_closes;
    lines_if_block_closes = 0;
  }

  // One line; false when reading ends with it.
  bool take_line(std::string_view line, bool ended) {
    ++number;
    if (!ended) {
      damaged_line("truncated: the last line has no end (the recorder was stopped while writing it?)");
      return false;
    }
    if (line.size() < kCrcSuffix || line.compare(line.size() - kCrcSuffix, 2, " *") != 0) {
      if (number == 1) throw InputError(path + ":1: no CRC at the end of the line: not a stridemap scan log");
      damaged_line("no CRC at the end of the line");
      return true;
    }
    const std::string_view body = line.substr(0, line.size() - kCrcSuffix);
    if (scan_log_crc(body) != line.substr(line.size() - 8)) {
      if (number == 1) throw InputError(path + ":1: CRC mismatch on the first line: not a readable stridemap scan log");
      damaged_line("CRC mismatch: the line is corrupted");
      return true;
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
      return true;
    }
    std::string_view kind;
    Fields(body).next(kind);
    const bool info_line = kind == "vv" || kind == "pp";
    if (!info_line && parser.in_block()) {
      if (const std::string problem = parser.close_block(); !problem.empty()) {
        stop_at(parser.block_line(), "sensor block: " + problem);
        return false;
      }
      if (log.damage.empty()) log.lines = number - 1;
      block_closed();
    }
    if (kind == kMagic) {
      // `record --append` after a torn last line: the new part starts here.
      if (log.damage.empty()) log.lines = number;
      return true;
    }
    if (const std::string problem = parser.record(body, number); !problem.empty()) {
      damaged_line(problem);
      return true;
    }
    if (!parser.in_block() && log.damage.empty()) log.lines = number;
    return true;
  }

  // After the last line read.
  void finish() {
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
  }

  std::string path;
  std::FILE* file = nullptr;
  char* line_buffer = nullptr;
  std::size_t line_capacity = 0;
  std::string_view content;
  std::size_t pos = 0;
  ScanLog log;
  UrgScan scan;
  bool scan_ready = false;
  LogParser parser;
  std::size_t number = 0;
  std::size_t lines_if_block_closes = 0;  // lines before the first damage, if the block it interrupted closes well
  bool stopped = false;
  bool done = false;
};

ScanLogReader::ScanLogReader(const std::string& path) : state_(std::make_unique<State>(path)) {
  refuse_folder(path, "the scan log");
  state_->file = std::fopen(path.c_str(), "rb");
  if (state_->file == nullptr) throw InputError(path + ": cannot open the scan log: " + std::strerror(errno));
}

ScanLogReader::ScanLogReader(std::string_view content, const std::string& source_name)
    : state_(std::make_unique<State>(source_name)) {
  state_->content = content;
}

ScanLogReader::~ScanLogReader() = default;
ScanLogReader::ScanLogReader(ScanLogReader&&) noexcept = default;
ScanLogReader& ScanLogReader::operator=(ScanLogReader&&) noexcept = default;

const UrgScan* ScanLogReader::next() {
  State& s = *state_;
  while (!s.done) {
    s.scan_ready = false;
    std::string_view line;
    bool ended = false;
    if (!s.read_line(line, ended) || !s.take_line(line, ended)) {
      s.done = true;
      s.finish();
      return nullptr;
    }
    if (s.scan_ready) {
      ++scans_;
      return &s.scan;
    }
  }
  return nullptr;
}

const ScanLog& ScanLogReader::log() const { return state_->log; }

ScanLog read_scan_log(const std::string& path) {
  ScanLogReader reader(path);
  std::vector<UrgScan> scans;
  while (const UrgScan* scan = reader.next()) scans.push_back(*scan);
  ScanLog log = reader.log();
  log.scans = std::move(scans);
  return log;
}

ScanLog parse_scan_log(std::string_view content, const std::string& source_name) {
  ScanLogReader reader(content, source_name);
  std::vector<UrgScan> scans;
  while (const UrgScan* scan = reader.next()) scans.push_back(*scan);
  ScanLog log = reader.log();
  log.scans = std::move(scans);
  return log;
}

}  // namespace stridemap::io
