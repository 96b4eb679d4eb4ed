#pragma once
// Recorded URG scans with their timestamps and the sensor's own description
// (VV, PP), as text: one record per line, each line closed by a CRC-32 so
// that damage anywhere is found, and a reader that skips (and counts) a
// damaged or truncated line and keeps every other record. The format is in
// docs/live.md ("Scan log format"), with the reasons for text.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "stridemap/sensors/scip_parameters.hpp"
#include "stridemap/sensors/urg_driver.hpp"

namespace stridemap::io {

inline constexpr int kScanLogVersion = 1;

struct LoggedFault {
  double host_time_s = 0.0;
  std::string kind;  ///< fault_name() of the driver's fault
  std::uint64_t count = 0;
  std::string message;
};

struct ScanLog {
  std::string device;                 ///< as recorded
  scip::VersionInfo version;
  scip::ScipParameters parameters;
  std::vector<UrgScan> scans;         ///< in recording order; raw.time_s = host_time_s
  std::vector<LoggedFault> faults;
  std::size_t connects = 0;
  /// Empty when every line was read; else "<file>:<line>: <what>" for the
  /// first damaged line.
  std::string damage;
  std::size_t lines = 0;               ///< lines read before the first damage
  /// Every damaged line skipped, by number (1-based); the first 20 also as
  /// "<file>:<line>: <what>" in `skipped`.
  std::vector<std::size_t> skipped_line_numbers;
  std::vector<std::string> skipped;
  /// Empty unless reading stopped early: "<file>:<line>: <what>" for damage
  /// inside a sensor block or a sensor with other parameters.
  std::string stop;
};

/// Reads a log record by record, holding one line and one scan: memory does
/// not grow with the log's length (`stridemap map --log`). The same reading,
/// damage handling and messages as read_scan_log, which is built on it.
class ScanLogReader {
 public:
  /// Opens the log; throws InputError naming the path when it cannot.
  explicit ScanLogReader(const std::string& path);
  /// A log's bytes in memory (they must outlive the reader); `source_name`
  /// stands for the file in messages.
  ScanLogReader(std::string_view content, const std::string& source_name);
  ~ScanLogReader();
  ScanLogReader(ScanLogReader&&) noexcept;
  ScanLogReader& operator=(ScanLogReader&&) noexcept;

  /// The next scan, valid until the next call (its storage is reused), or
  /// null at the end of what can be read. Throws InputError as read_scan_log
  /// does: the first line, the first sensor block, no sensor parameters at
  /// all (found at the end), or a read error.
  const UrgScan* next();
  /// What was read so far, scans aside (`scans` stays empty); complete once
  /// next() returned null. `parameters` is set once next() returned a scan.
  const ScanLog& log() const;
  /// Scans returned so far.
  std::size_t scans() const { return scans_; }

 private:
  struct State;
  std::unique_ptr<State> state_;
  std::size_t scans_ = 0;
};

/// Reads a log. Throws InputError naming the file for a file that cannot be
/// opened or is not a scan log (first line), or whose first sensor block is
/// damaged; a later damaged line is skipped and reported in ScanLog::skipped,
/// damage in a later sensor block ends reading there (ScanLog::stop).
ScanLog read_scan_log(const std::string& path);
/// The same from a log's bytes in memory; `source_name` stands for the file
/// in messages.
ScanLog parse_scan_log(std::string_view content, const std::string& source_name);

/// Writes a log as it is recorded: each record is written and flushed as a
/// whole line, so a killed recorder leaves at most one partial last line.
class ScanLogWriter {
 public:
  /// Creates (truncates) `path`, or with `append` adds to it: a torn last
  /// line left by a killed recorder is ended first, so it stays one damaged
  /// line that readers skip. Callers check first that truncating is wanted
  /// (docs/live.md). Throws InputError naming the path on failure.
  ScanLogWriter(const std::string& path, const std::string& device, bool append = false);
  ~ScanLogWriter();
  ScanLogWriter(const ScanLogWriter&) = delete;
  ScanLogWriter& operator=(const ScanLogWriter&) = delete;

  /// The sensor's VV and PP replies; written at every (re)connection.
  void write_sensor(double host_time_s, const scip::VersionInfo& version, const scip::ScipParameters& parameters);
  void write_scan(const UrgScan& scan);
  void write_fault(double host_time_s, UrgFault fault, std::uint64_t count, const std::string& message);
  /// Throws InputError when a write failed (disk full...).
  void flush();
  const std::string& path() const { return path_; }

 private:
  void write_line(std::string& body);
  std::string path_;
  std::FILE* file_ = nullptr;
  bool failed_ = false;
  std::string line_;
};

/// The CRC-32 (zlib's) of a line body, as 8 lower-case hex digits.
std::string scan_log_crc(std::string_view body);

}  // namespace stridemap::io
