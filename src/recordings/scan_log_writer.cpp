// Writing a scan log (scan_log.cpp reads it): one record per line, each
// flushed whole with its CRC, so a killed recorder leaves at most one torn line.
#include <cerrno>
#include <charconv>
#include <cstdio>
#include <cstring>

#include "stridemap/core/error.hpp"
#include "stridemap/recordings/scan_log.hpp"

namespace stridemap::io {
namespace {

constexpr std::string_view kLogMagic = "stridemap-urg-log";

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

}  // namespace

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
    body = std::string(kLogMagic) + " " + std::to_string(kScanLogVersion);
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
