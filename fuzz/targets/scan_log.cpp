// Scan logs (recordings/scan_log.hpp, docs/live.md). Two kinds of input, by the
// first byte:
//  - even: the bytes are a log. Whatever the reader keeps must be exactly
//    what it reads from the same lines without the ones it skipped (and
//    without everything from where it stopped): parsing those gives the
//    same log, with no damage.
//  - odd: the bytes describe a log (sensor blocks, scans, faults with any
//    values the driver can produce) and one damage (cut, overwritten,
//    inserted or deleted byte). The log is written with ScanLogWriter,
//    damaged, and read: every record on a line the damage did not touch
//    comes back unchanged (one bad line costs one record), the damage is
//    reported at its line; damage in a sensor block loses at most what
//    follows it, and in the first block is an InputError naming the file.
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "fuzz_input.hpp"
#include "fuzz_target.hpp"
#include "stridemap/core/error.hpp"
#include "stridemap/recordings/scan_log.hpp"

namespace scan_log_fuzz {
namespace {

using namespace stridemap;
using fuzz::check;

const std::string kName = "fuzz.urglog";

bool starts_with(const std::string& text, const std::string& prefix) { return text.rfind(prefix, 0) == 0; }

bool same_scan(const UrgScan& a, const UrgScan& b) {
  return a.sequence == b.sequence && fuzz::same_number(a.host_time_s, b.host_time_s) &&
         fuzz::same_number(a.host_receive_time_s, b.host_receive_time_s) &&
         fuzz::same_number(a.raw.time_s, b.raw.time_s) && a.sensor_timestamp_ms == b.sensor_timestamp_ms &&
         a.sensor_time_ms == b.sensor_time_ms && a.lost_before == b.lost_before &&
         a.first_after_start == b.first_after_start && a.raw.first_step == b.raw.first_step &&
         a.raw.cluster == b.raw.cluster && a.raw.values_mm == b.raw.values_mm;
}

bool same_fault(const io::LoggedFault& a, const io::LoggedFault& b) {
  return fuzz::same_number(a.host_time_s, b.host_time_s) && a.kind == b.kind && a.count == b.count &&
         a.message == b.message;
}

void check_same_log(const io::ScanLog& a, const io::ScanLog& b, const std::string& what) {
  check(a.device == b.device, what + ": device differs");
  check(a.parameters == b.parameters, what + ": parameters differ");
  check(a.version == b.version, what + ": version differs");
  check(a.connects == b.connects, what + ": connects " + std::to_string(a.connects) + " vs " + std::to_string(b.connects));
  check(a.scans.size() == b.scans.size(),
        what + ": " + std::to_string(a.scans.size()) + " vs " + std::to_string(b.scans.size()) + " scans");
  for (std::size_t i = 0; i < a.scans.size(); ++i) check(same_scan(a.scans[i], b.scans[i]), what + ": scan " + std::to_string(i));
  check(a.faults.size() == b.faults.size(), what + ": fault count differs");
  for (std::size_t i = 0; i < a.faults.size(); ++i) check(same_fault(a.faults[i], b.faults[i]), what + ": fault " + std::to_string(i));
}

// Byte offsets where lines start (a final offset = size when it ends with LF).
std::vector<std::size_t> line_starts(std::string_view text) {
  std::vector<std::size_t> starts{0};
  for (std::size_t i = 0; i < text.size(); ++i) {
    if (text[i] == '\n') starts.push_back(i + 1);
  }
  return starts;
}

void raw_log(std::string_view bytes) {
  io::ScanLog log;
  try {
    log = io::parse_scan_log(bytes, kName);
  } catch (const InputError& e) {
    check(starts_with(e.what(), kName), std::string("an error that does not name the log: ") + e.what());
    return;
  }
  (void)scip::to_urg_parameters(log.parameters);  // parameters the reader keeps are usable
  for (const UrgScan& s : log.scans) {
    check(s.raw.values_mm.size() <= 10000, "a scan longer than a URG sends");
    for (const std::uint32_t v : s.raw.values_mm) check(v < (1u << 18), "a value no URG can send");
  }
  const std::vector<std::size_t> starts = line_starts(bytes);
  if (log.damage.empty()) {
    check(log.skipped_line_numbers.empty() && log.stop.empty(), "lines skipped without damage reported");
    return;
  }
  const std::size_t colon = log.damage.find(':', kName.size() + 1);
  check(starts_with(log.damage, kName + ":") && colon != std::string::npos, "damage without its place: " + log.damage);
  const std::size_t damage_line = std::stoul(log.damage.substr(kName.size() + 1, colon - kName.size() - 1));
  check(damage_line > log.lines && damage_line <= starts.size(),
        "damage '" + log.damage + "' is not at a line after the " + std::to_string(log.lines) + " kept");
  std::size_t stop_line = starts.size() + 1;
  if (!log.stop.empty()) {
    const std::size_t c = log.stop.find(':', kName.size() + 1);
    check(starts_with(log.stop, kName + ":") && c != std::string::npos, "stop without its place: " + log.stop);
    stop_line = std::stoul(log.stop.substr(kName.size() + 1, c - kName.size() - 1));
  }
  // The same lines without the skipped ones, up to the stop, read alike and undamaged.
  std::string kept;
  std::size_t skipped = 0;
  for (std::size_t line = 1; line <= starts.size() && line < stop_line; ++line) {
    if (skipped < log.skipped_line_numbers.size() && log.skipped_line_numbers[skipped] == line) {
      ++skipped;
      continue;
    }
    const std::size_t from = starts[line - 1];
    const std::size_t to = line < starts.size() ? starts[line] : bytes.size();
    kept.append(bytes.substr(from, to - from));
  }
  io::ScanLog again;
  try {
    again = io::parse_scan_log(kept, kName);
  } catch (const InputError& e) {
    fuzz::failure(std::string("the lines kept are rejected on their own: ") + e.what());
  }
  check(again.damage.empty(), "the lines kept are damaged on their own: " + again.damage);
  check_same_log(log, again, "the log without its skipped lines read alone");
}

// What the writer is given; and the line each record ends on.
struct Written {
  io::ScanLog log;                      // as expected when nothing is damaged
  std::vector<std::size_t> scan_line, fault_line;
  struct Block {
    std::size_t last_line;
    scip::VersionInfo version;
  };
  std::vector<Block> blocks;
};

std::string printable_text(fuzz::ByteReader& in, std::size_t max) {
  std::string s = in.text(max);
  for (char& c : s) {
    if (c == '\n' || c == '\r') c = ' ';  // what the writer does to a record's text
  }
  return s;
}

void damaged_log(fuzz::ByteReader& in) {
  static const std::string path =
      (std::filesystem::temp_directory_path() / ("stridemap_fuzz_scan_log_" + std::to_string(::getpid()))).string();
  Written w;
  scip::ScipParameters parameters;
  if (in.byte() % 2) {
    parameters.model = printable_text(in, 40);
    parameters.first_step = static_cast<int>(in.in_range(0, 100));
    parameters.last_step = static_cast<int>(in.in_range(static_cast<std::uint64_t>(parameters.first_step), 768));
    parameters.front_step =
        static_cast<int>(in.in_range(static_cast<std::uint64_t>(parameters.first_step),
                                     static_cast<std::uint64_t>(parameters.last_step)));
  }
  const auto version = [&] {
    return scip::VersionInfo{"Hokuyo Automatic Co.,Ltd.", printable_text(in, 30), "3.3.00", "SCIP 2.0",
                             printable_text(in, 12)};
  };
  std::size_t lines = 0;
  {
    w.log.device = printable_text(in, 30);
    io::ScanLogWriter writer(path, w.log.device);
    lines = 2;
    const auto sensor_block = [&] {
      const scip::VersionInfo v = version();
      writer.write_sensor(in.any_double(), v, parameters);
      lines += 1 + scip::to_info_fields(v).size() + scip::to_info_fields(parameters).size();
      w.blocks.push_back({lines, v});
    };
    sensor_block();
    for (int records = 0; records < 40 && !in.empty(); ++records) {
      const std::uint8_t op = in.byte() % 8;
      if (op == 0) {
        sensor_block();
      } else if (op == 1) {
        io::LoggedFault f;
        f.host_time_s = in.any_double();
        const auto fault = static_cast<UrgFault>(in.in_range(0, 10));
        f.kind = std::string(fault_name(fault));
        f.count = in.integer<std::uint64_t>();
        f.message = printable_text(in, 60);
        writer.write_fault(f.host_time_s, fault, f.count, f.message);
        w.log.faults.push_back(f);
        w.fault_line.push_back(++lines);
      } else {
        UrgScan s;
        s.sequence = in.integer<std::uint64_t>();
        s.host_time_s = in.any_double();
        s.raw.time_s = s.host_time_s;
        s.host_receive_time_s = in.any_double();
        s.sensor_timestamp_ms = in.integer<std::uint32_t>() & 0xFFFFFFu;
        s.sensor_time_ms = in.integer<std::uint64_t>();
        s.lost_before = in.integer<std::uint64_t>();
        s.first_after_start = in.byte() & 1;
        s.raw.first_step = static_cast<int>(in.in_range(0, 9999));
        s.raw.cluster = static_cast<int>(in.in_range(0, 99));
        s.raw.values_mm.resize(in.in_range(0, 24));
        for (std::uint32_t& v : s.raw.values_mm) v = in.integer<std::uint32_t>() & 0x3FFFFu;
        writer.write_scan(s);
        w.log.scans.push_back(s);
        w.scan_line.push_back(++lines);
      }
    }
  }
  std::ifstream file(path, std::ios::binary);
  std::string text{std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>()};
  std::filesystem::remove(path);
  const std::vector<std::size_t> starts = line_starts(text);
  check(starts.size() == lines + 1 && starts.back() == text.size(), "the writer wrote " +
                                                                        std::to_string(starts.size() - 1) + " lines, not " +
                                                                        std::to_string(lines));

  // The damage, and the first line it touches.
  const std::uint8_t kind = in.byte() % 5;
  const std::size_t at = in.integer<std::uint32_t>() % text.size();
  const char value = static_cast<char>(in.byte());
  bool damaged = true, newline_after_line_end = false;
  switch (kind) {
    case 0: damaged = false; break;
    case 1: text.resize(at); break;
    case 2:
      damaged = text[at] != value;
      text[at] = value;
      break;
    case 3:
      // An LF put just before a line's own LF leaves that line whole: the
      // damage is the empty line after it.
      newline_after_line_end = value == '\n' && text[at] == '\n';
      text.insert(text.begin() + static_cast<std::ptrdiff_t>(at), value);
      break;
    case 4: text.erase(at, 1); break;
  }
  std::size_t line = lines + 1;  // first damaged line, 1-based
  if (damaged) {
    line = 1;
    while (line < starts.size() && starts[line] <= at) ++line;
    if (newline_after_line_end) ++line;
  }
  // A cut at a line start leaves a shorter log with nothing damaged.
  const bool cut_at_line_end = kind == 1 && starts[line - 1] == at;
  // The written lines whose records are lost: the damaged one; the next one
  // too when an LF between them went (overwritten or deleted); every one
  // from it on for a cut.
  const bool merged = (kind == 2 || kind == 4) && damaged && starts[line] == at + 1;
  // An LF inserted at a line's start makes an empty line before it: only that is damaged.
  const bool empty_line_inserted = kind == 3 && value == '\n' && at == starts[line - 1];
  const std::size_t first_lost = line;
  std::size_t last_lost = !damaged || newline_after_line_end || empty_line_inserted ? 0 : merged ? line + 1 : line;
  if (kind == 1) last_lost = lines;
  const auto lost = [&](std::size_t l) { return damaged && l >= first_lost && l <= last_lost; };
  bool block_touched = (last_lost >= first_lost && first_lost <= 2) || (damaged && line == 1);
  for (const Written::Block& b : w.blocks) {
    const std::size_t first = b.last_line - scip::to_info_fields(b.version).size() -
                              scip::to_info_fields(parameters).size();
    for (std::size_t l = first; l <= b.last_line; ++l) block_touched = block_touched || lost(l);
  }

  io::ScanLog log;
  try {
    log = io::parse_scan_log(text, kName);
  } catch (const InputError& e) {
    check(block_touched, "a log damaged at line " + std::to_string(line) + ", outside every sensor block, is rejected: " +
                             e.what());
    check(starts_with(e.what(), kName), std::string("an error that does not name the log: ") + e.what());
    return;
  }
  if (block_touched) {
    // What is kept is written records, in order: nothing invented.
    std::size_t next = 0;
    for (const UrgScan& s : log.scans) {
      while (next < w.log.scans.size() && !same_scan(w.log.scans[next], s)) ++next;
      check(next < w.log.scans.size(), "a scan that was never written came back");
      ++next;
    }
    return;
  }
  if (damaged && !cut_at_line_end) {
    check(starts_with(log.damage, kName + ":" + std::to_string(line) + ": "),
          "damage at line " + std::to_string(line) + " reported as '" + log.damage + "'");
  } else {
    check(log.damage.empty(), "an undamaged log reported as damaged: " + log.damage);
  }
  check(log.stop.empty(), "reading stopped at damage outside every sensor block: " + log.stop);
  io::ScanLog expected;
  expected.device = w.log.device;
  expected.parameters = parameters;
  for (const Written::Block& b : w.blocks) {
    expected.version = b.version;
    ++expected.connects;
  }
  for (std::size_t i = 0; i < w.log.scans.size(); ++i) {
    if (!lost(w.scan_line[i])) expected.scans.push_back(w.log.scans[i]);
  }
  for (std::size_t i = 0; i < w.log.faults.size(); ++i) {
    if (!lost(w.fault_line[i])) expected.faults.push_back(w.log.faults[i]);
  }
  check_same_log(log, expected, "the records on the lines the damage did not touch");
}

}  // namespace

STRIDEMAP_FUZZ_TARGET(scan_log) {
  if (data.empty()) return;
  if (data[0] % 2 == 0) {
    raw_log(fuzz::as_text(data.subspan(1)));
  } else {
    fuzz::ByteReader in(data.subspan(1));
    damaged_log(in);
  }
}

}  // namespace scan_log_fuzz
