// The scan log: what is written reads back bit for bit, and damage
// (truncation, a corrupted byte, an impossible record) costs only the
// damaged line, named with its place; damage in a sensor block stops
// reading there.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "live/test_folder.hpp"
#include "stridemap/core/error.hpp"
#include "stridemap/recordings/scan_log.hpp"

namespace stridemap::io {
namespace {

UrgScan make_scan(std::uint64_t k) {
  UrgScan s;
  s.sequence = k;
  s.sensor_timestamp_ms = static_cast<std::uint32_t>(((1u << 24) - 200 + 100 * k) % (1u << 24));
  s.sensor_time_ms = (1u << 24) - 200 + 100 * k;
  s.host_time_s = 1733065200.0 + 0.1 * static_cast<double>(k) + 1.0 / 3.0;
  s.host_receive_time_s = s.host_time_s + 0.1003;
  s.lost_before = k == 3 ? 2 : 0;
  s.first_after_start = k == 0;
  s.raw.first_step = 44;
  s.raw.cluster = 1;
  s.raw.time_s = s.host_time_s;
  for (int i = 0; i < 682; ++i) s.raw.values_mm.push_back(static_cast<std::uint32_t>((i * 37 + k) % 5600));
  return s;
}

std::string write_log(const test::TestFolder& dir, std::size_t scans) {
  const std::string path = dir / "log.txt";
  ScanLogWriter writer(path, "/dev/ttyACM0");
  scip::VersionInfo version{"Hokuyo Automatic Co.,Ltd.", "SOKUIKI Sensor URG-04LX", "3.3.00", "SCIP 2.0", "H0000"};
  writer.write_sensor(1733065200.0, version, scip::ScipParameters{});
  for (std::size_t k = 0; k < scans; ++k) {
    writer.write_scan(make_scan(k));
    if (k == 2) writer.write_fault(1733065200.4, UrgFault::scans_lost, 2, "2 scan(s) missing\nbetween 300 and 600 ms");
  }
  return path;
}

TEST(ScanLog, RoundTripIsExact) {
  test::TestFolder dir;
  const ScanLog log = read_scan_log(write_log(dir, 5));
  EXPECT_TRUE(log.damage.empty()) << log.damage;
  EXPECT_EQ(log.device, "/dev/ttyACM0");
  EXPECT_EQ(log.parameters, scip::ScipParameters{});
  EXPECT_EQ(log.version.serial, "H0000");
  EXPECT_EQ(log.connects, 1u);
  ASSERT_EQ(log.scans.size(), 5u);
  for (std::size_t k = 0; k < 5; ++k) {
    const UrgScan expected = make_scan(k);
    const UrgScan& got = log.scans[k];
    EXPECT_EQ(got.sequence, expected.sequence);
    EXPECT_EQ(got.sensor_timestamp_ms, expected.sensor_timestamp_ms);
    EXPECT_EQ(got.sensor_time_ms, expected.sensor_time_ms);
    EXPECT_EQ(got.host_time_s, expected.host_time_s);  // bit for bit
    EXPECT_EQ(got.host_receive_time_s, expected.host_receive_time_s);
    EXPECT_EQ(got.lost_before, expected.lost_before);
    EXPECT_EQ(got.first_after_start, expected.first_after_start);
    EXPECT_EQ(got.raw.values_mm, expected.raw.values_mm);
  }
  ASSERT_EQ(log.faults.size(), 1u);
  EXPECT_EQ(log.faults[0].kind, "scans_lost");
  EXPECT_EQ(log.faults[0].count, 2u);
  EXPECT_EQ(log.faults[0].message, "2 scan(s) missing between 300 and 600 ms");  // one line, whatever it held
}

TEST(ScanLog, TruncatedLastLineKeepsEveryScanBeforeIt) {
  test::TestFolder dir;
  const std::string path = write_log(dir, 6);
  std::string text = dir.read("log.txt");
  text.resize(text.size() - 1500);  // killed while writing the last scan
  dir.write("log.txt", text);
  const ScanLog log = read_scan_log(path);
  EXPECT_EQ(log.scans.size(), 5u);
  EXPECT_NE(log.damage.find("log.txt:23: truncated"), std::string::npos) << log.damage;
}

// Each line has its own CRC: one flipped byte loses one scan, not the rest.
TEST(ScanLog, CorruptedByteLosesOnlyItsLine) {
  test::TestFolder dir;
  const std::string path = write_log(dir, 6);
  std::string text = dir.read("log.txt");
  const auto flip_in_line = [&](int wanted) {
    std::size_t line_start = 0;
    for (int line = 1; line < wanted; ++line) line_start = text.find('\n', line_start) + 1;
    text[line_start + 300] = text[line_start + 300] == '1' ? '2' : '1';
  };
  flip_in_line(19);  // scan 2
  flip_in_line(22);  // scan 4
  dir.write("log.txt", text);
  const ScanLog log = read_scan_log(path);
  ASSERT_EQ(log.scans.size(), 4u);
  EXPECT_EQ(log.scans[0].sequence, 0u);
  EXPECT_EQ(log.scans[1].sequence, 1u);
  EXPECT_EQ(log.scans[2].sequence, 3u);
  EXPECT_EQ(log.scans[3].sequence, 5u);
  EXPECT_EQ(log.faults.size(), 1u);  // line 20, between the damaged ones
  EXPECT_EQ(log.skipped_line_numbers, (std::vector<std::size_t>{19, 22}));
  ASSERT_EQ(log.skipped.size(), 2u);
  EXPECT_NE(log.skipped[0].find("log.txt:19: CRC mismatch"), std::string::npos) << log.skipped[0];
  EXPECT_NE(log.skipped[1].find("log.txt:22: CRC mismatch"), std::string::npos) << log.skipped[1];
  EXPECT_NE(log.damage.find("log.txt:19: CRC mismatch"), std::string::npos) << log.damage;
  EXPECT_TRUE(log.stop.empty()) << log.stop;
}

// `record --append` after a recorder was killed mid-line: the torn line
// stays one damaged line; everything before and after it is read.
TEST(ScanLog, AppendingAfterATornLineKeepsBothParts) {
  test::TestFolder dir;
  const std::string path = write_log(dir, 3);
  std::string text = dir.read("log.txt");
  text.resize(text.size() - 700);  // killed while writing the last scan
  dir.write("log.txt", text);
  {
    ScanLogWriter writer(path, "/dev/ttyACM1", true);
    scip::VersionInfo version{"Hokuyo Automatic Co.,Ltd.", "SOKUIKI Sensor URG-04LX", "3.3.00", "SCIP 2.0", "H0000"};
    writer.write_sensor(1733065300.0, version, scip::ScipParameters{});
    writer.write_scan(make_scan(7));
  }
  const ScanLog log = read_scan_log(path);
  ASSERT_EQ(log.scans.size(), 3u);  // scans 0, 1 and the new 7; the torn scan 2 is skipped
  EXPECT_EQ(log.scans[2].sequence, 7u);
  EXPECT_EQ(log.connects, 2u);
  EXPECT_EQ(log.device, "/dev/ttyACM1");
  EXPECT_EQ(log.skipped_line_numbers.size(), 1u);
  EXPECT_TRUE(log.stop.empty()) << log.stop;
}

TEST(ScanLog, DamageInsideTheSensorBlockLeavesNothingUsableAndIsAnError) {
  test::TestFolder dir;
  const std::string path = write_log(dir, 3);
  std::string text = dir.read("log.txt");
  text[text.find("AMAX:725") + 5] = '9';
  dir.write("log.txt", text);
  try {
    read_scan_log(path);
    ADD_FAILURE() << "damaged parameters accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("log.txt:14: CRC mismatch"), std::string::npos) << e.what();
  }
}

TEST(ScanLog, FilesThatAreNoLogOrHaveNoParametersAreErrors) {
  test::TestFolder dir;
  const auto message = [](const std::string& path) {
    try {
      read_scan_log(path);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message(dir.write("a.txt", "1 2 3\n")).find("a.txt:1: no CRC"), std::string::npos);
  const std::string magic_only = "stridemap-urg-log 1 *" + scan_log_crc("stridemap-urg-log 1") + "\n";
  EXPECT_NE(message(dir.write("b.txt", magic_only)).find("holds no sensor parameters"), std::string::npos);
  const std::string future = "stridemap-urg-log 7 *" + scan_log_crc("stridemap-urg-log 7") + "\n";
  EXPECT_NE(message(dir.write("c.txt", future)).find("version 7 is not supported"), std::string::npos);
  const std::string other = "hello 1 *" + scan_log_crc("hello 1") + "\n";
  EXPECT_NE(message(dir.write("d.txt", other)).find("not a stridemap scan log"), std::string::npos);
  const std::string scan_first = magic_only + "scan 0 1 1 0 0 0 1 44 1 0 *" + scan_log_crc("scan 0 1 1 0 0 0 1 44 1 0") + "\n";
  EXPECT_NE(message(dir.write("e.txt", scan_first)).find("e.txt:2: a scan before the sensor's parameters"),
            std::string::npos);
  EXPECT_NE(message(dir / "missing.txt").find("cannot open the scan log"), std::string::npos);
  EXPECT_THROW(ScanLogWriter(dir / "no/such/folder/log.txt", "x"), InputError);
}

// The recorder killed while writing the first scan: the sensor block before
// it is complete, so the log is usable (no scans yet) and the damage named.
TEST(ScanLog, CutWhileWritingTheFirstScanKeepsTheSensorsParameters) {
  test::TestFolder dir;
  const std::string path = write_log(dir, 1);
  std::string text = dir.read("log.txt");
  text.resize(text.find("\nscan ") + 40);
  dir.write("log.txt", text);
  const ScanLog log = read_scan_log(path);
  EXPECT_TRUE(log.scans.empty());
  EXPECT_EQ(log.connects, 1u);
  EXPECT_EQ(log.parameters, scip::ScipParameters{});
  EXPECT_EQ(log.lines, 16u);
  EXPECT_NE(log.damage.find("log.txt:17: truncated"), std::string::npos) << log.damage;
}

// A later sensor block (a reconnection) is kept only whole and only with the
// same parameters; otherwise reading stops at that block's first line.
TEST(ScanLog, ReconnectionBlockWithOtherParametersOrCutShortStopsAtTheBlock) {
  test::TestFolder dir;
  const std::string path = dir / "log.txt";
  scip::VersionInfo version{"Hokuyo Automatic Co.,Ltd.", "SOKUIKI Sensor URG-04LX", "3.3.00", "SCIP 2.0", "H0000"};
  scip::ScipParameters other;
  other.last_step = 700;
  {
    ScanLogWriter writer(path, "/dev/ttyACM0");
    writer.write_sensor(1.0, version, scip::ScipParameters{});
    writer.write_scan(make_scan(0));
    writer.write_sensor(2.0, version, other);  // lines 18-31
    writer.write_scan(make_scan(1));
  }
  ScanLog log = read_scan_log(path);
  EXPECT_EQ(log.scans.size(), 1u);
  EXPECT_EQ(log.lines, 17u);
  EXPECT_EQ(log.damage.rfind(path + ":18: sensor block: the sensor's parameters changed", 0), 0u) << log.damage;
  EXPECT_EQ(log.stop, log.damage);
  // The same log cut at a line end inside the second block.
  std::string text = dir.read("log.txt");
  std::size_t cut = 0;
  for (int line = 0; line < 25; ++line) cut = text.find('\n', cut) + 1;
  dir.write("log.txt", text.substr(0, cut));
  log = read_scan_log(path);
  EXPECT_EQ(log.scans.size(), 1u);
  EXPECT_EQ(log.connects, 1u);
  EXPECT_EQ(log.damage.rfind(path + ":18: sensor block: SCIP PP reply", 0), 0u) << log.damage;
}

TEST(ScanLog, ValuesNoUrgCanSendAreDamage) {
  test::TestFolder dir;
  const std::string path = write_log(dir, 2);
  std::string text = dir.read("log.txt");
  const std::string body = "scan 9 3 3 0 0 0 0 44 1 2 5 262144";
  text += body + " *" + scan_log_crc(body) + "\n";
  const std::string next = "scan 10 4 4 0 0 0 0 44 1 2 5 6";
  text += next + " *" + scan_log_crc(next) + "\n";
  dir.write("log.txt", text);
  const ScanLog log = read_scan_log(path);
  ASSERT_EQ(log.scans.size(), 3u);  // the bad record skipped, the one after it kept
  EXPECT_EQ(log.scans[2].sequence, 10u);
  EXPECT_NE(log.damage.find("log.txt:19: scan: value 2 (262144) is more than a URG can send (262143)"), std::string::npos)
      << log.damage;
}

TEST(ScanLog, ReadFromMemoryNamesTheSource) {
  test::TestFolder dir;
  write_log(dir, 3);
  const std::string text = dir.read("log.txt");
  const ScanLog log = parse_scan_log(text.substr(0, text.size() - 5), "camera-pc:/logs/run.urglog");
  EXPECT_EQ(log.scans.size(), 3u);
  EXPECT_EQ(log.damage.rfind("camera-pc:/logs/run.urglog:20: truncated", 0), 0u) << log.damage;
}

}  // namespace
}  // namespace stridemap::io
