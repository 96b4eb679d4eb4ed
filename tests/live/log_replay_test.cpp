// `map --log` reads the log as a stream (LogReplay over io::ScanLogReader):
// the map, the counts and the log's damage report are those of mapping the
// whole log read into memory first (io::read_scan_log), as the tool did
// before, on logs with damaged lines, a torn last line and a sensor block
// that ends the reading; errors still name the file and the line.
#include <gtest/gtest.h>

#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include "live/test_folder.hpp"
#include "stridemap/core/error.hpp"
#include "stridemap/core/exported_map.hpp"
#include "stridemap/live/log_replay.hpp"
#include "stridemap/recordings/pose_stream.hpp"
#include "stridemap/recordings/scan_log.hpp"

namespace stridemap {
namespace {

UrgScan ground_scan(std::size_t k) {
  UrgScan s;
  s.sequence = k;
  s.host_time_s = 50.0 + 0.1 * static_cast<double>(k);
  s.host_receive_time_s = s.host_time_s + 0.02;
  s.sensor_time_ms = 50000 + 100 * k + 7;  // on the poses' clock too (--clock sensor)
  s.sensor_timestamp_ms = static_cast<std::uint32_t>(s.sensor_time_ms);
  s.raw.first_step = 44;
  s.raw.cluster = 1;
  for (std::size_t i = 0; i < 682; ++i) s.raw.values_mm.push_back(380 + static_cast<std::uint32_t>((k * 11 + i * 17) % 90));
  return s;
}

// A log of `scans` scans; damaged lines among them, a torn last line when asked.
std::string write_log(const test::TestFolder& dir, std::size_t scans, bool damage, bool other_sensor_at_end) {
  const std::string path = dir / "log.txt";
  const scip::VersionInfo version{"Hokuyo Automatic Co.,Ltd.", "SOKUIKI Sensor URG-04LX", "3.3.00", "SCIP 2.0", "H1"};
  {
    io::ScanLogWriter writer(path, "/dev/ttyACM0");
    writer.write_sensor(49.0, version, scip::ScipParameters{});
    for (std::size_t k = 0; k < scans; ++k) {
      writer.write_scan(ground_scan(k));
      if (k == scans / 2) writer.write_fault(60.0, UrgFault::scans_lost, 1, "1 scan missing");
    }
    if (other_sensor_at_end) {
      scip::ScipParameters other;
      other.max_distance_mm = 4000;
      writer.write_sensor(200.0, version, other);
      writer.write_scan(ground_scan(scans));
    }
  }
  if (damage) {
    std::string text = dir.read("log.txt");
    // One flipped digit in a scan line (its CRC no longer matches), a line
    // that is not a record, and a torn last line.
    const std::size_t third = text.find("\nscan 3 ");
    text[third + 20] = text[third + 20] == '1' ? '2' : '1';
    text.insert(text.find("\nscan 9 ") + 1, "not a record\n");
    text += "scan 999 12";
    std::ofstream(path, std::ios::binary | std::ios::trunc) << text;
  }
  return path;
}

std::vector<TimedPose> pose_list(std::size_t scans) {
  std::vector<TimedPose> poses;
  for (std::size_t k = 0; k <= scans + 2; ++k) {
    TimedPose p;
    p.time_s = 50.0 + 0.1 * static_cast<double>(k) - 0.05;
    p.pose.x_m = 0.03 * static_cast<double>(k);
    p.pose.y_m = 0.01 * static_cast<double>(k);
    poses.push_back(p);
  }
  return poses;
}

PoseTrack poses_for(std::size_t scans) {
  PoseTrack track(1.0);
  for (const TimedPose& p : pose_list(scans)) track.append(p);
  return track;
}

void expect_same_layers(const ExportedMap& a, const ExportedMap& b) {
  ASSERT_EQ(a.layers.size(), b.layers.size());
  EXPECT_EQ(a.min_cell, b.min_cell);
  for (std::size_t l = 0; l < a.layers.size(); ++l) {
    const ExportedLayer& x = a.layers[l];
    const ExportedLayer& y = b.layers[l];
    ASSERT_EQ(x.spec.name, y.spec.name);
    ASSERT_EQ(x.f32.size(), y.f32.size());
    // Bit for bit, NaN included (memcmp of an empty layer's null data is undefined).
    if (x.f32.size() > 0) {
      EXPECT_EQ(0, std::memcmp(x.f32.data(), y.f32.data(), sizeof(float) * static_cast<std::size_t>(x.f32.size())))
          << x.spec.name;
    }
    EXPECT_TRUE(x.u16 == y.u16) << x.spec.name;
    EXPECT_TRUE(x.u8 == y.u8) << x.spec.name;
  }
}

void expect_streamed_equals_whole(const std::string& path, std::size_t scans, LiveClock clock) {
  ScanMapperOptions options;
  options.filters = {ScanFilterKind::scan_sequence};
  // As `map --log` mapped before it streamed: the whole log read first.
  const io::ScanLog whole = io::read_scan_log(path);
  ScanMapper reference(options, scip::to_urg_parameters(whole.parameters));
  PoseTrack reference_poses = poses_for(scans);
  for (const UrgScan& scan : whole.scans) {
    UrgRawScan raw = scan.raw;
    raw.time_s = clock == LiveClock::sensor ? sensor_time_seconds(scan.sensor_time_ms) : scan.host_time_s;
    reference.add(raw);
    reference.process(reference_poses, true);
  }
  reference.finish();

  LogReplay replay(path, options, clock);
  PoseTrack poses = poses_for(scans);
  std::size_t told = 0;
  replay.run(poses, [&](std::size_t n) { told = n; });
  EXPECT_EQ(told, whole.scans.size());
  EXPECT_EQ(replay.scans_read(), whole.scans.size());
  const ScanMapperStats& a = replay.mapper().stats();
  const ScanMapperStats& b = reference.stats();
  EXPECT_EQ(a.scans, b.scans);
  EXPECT_EQ(a.integrated, b.integrated);
  EXPECT_EQ(a.after_last_pose, b.after_last_pose);
  EXPECT_EQ(a.before_first_pose, b.before_first_pose);
  EXPECT_GT(a.integrated, 0u);
  expect_same_layers(export_map(replay.mapper().map()), export_map(reference.map()));
  expect_same_layers(replay.mapper().filled_layers(), reference.filled_layers());

  // The poses read from their file in step with the scans, as `map --log` does.
  const std::string pose_path = path + ".poses";
  {
    std::ofstream out(pose_path);
    for (const TimedPose& p : pose_list(scans)) out << io::format_pose_line(p) << "\n";
  }
  io::PoseFileCursor cursor(pose_path);
  LogReplay streamed(path, options, clock);
  streamed.read_poses_with([&cursor](double time_s, PoseTrack& t) { cursor.read_to(time_s, t); });
  PoseTrack streamed_poses(1.0);
  streamed.run(streamed_poses);
  EXPECT_EQ(streamed.mapper().stats().integrated, b.integrated);
  EXPECT_EQ(streamed.mapper().stats().after_last_pose, b.after_last_pose);
  expect_same_layers(export_map(streamed.mapper().map()), export_map(reference.map()));
  const io::ScanLog& log = replay.log();
  EXPECT_TRUE(log.scans.empty());
  EXPECT_EQ(log.damage, whole.damage);
  EXPECT_EQ(log.lines, whole.lines);
  EXPECT_EQ(log.skipped, whole.skipped);
  EXPECT_EQ(log.skipped_line_numbers, whole.skipped_line_numbers);
  EXPECT_EQ(log.stop, whole.stop);
  EXPECT_EQ(log.faults.size(), whole.faults.size());
  EXPECT_EQ(log.connects, whole.connects);
}

TEST(LogReplay, StreamedMapIsTheMapOfTheWholeLog) {
  test::TestFolder dir;
  expect_streamed_equals_whole(write_log(dir, 120, false, false), 120, LiveClock::host);
}

TEST(LogReplay, DamagedLinesAndATornEndAreSkippedAsBefore) {
  test::TestFolder dir;
  const std::string path = write_log(dir, 120, true, false);
  expect_streamed_equals_whole(path, 120, LiveClock::sensor);
  LogReplay replay(path, ScanMapperOptions{}, LiveClock::host);
  PoseTrack poses = poses_for(120);
  replay.run(poses);
  ASSERT_EQ(replay.log().skipped_line_numbers.size(), 3u);
  EXPECT_NE(replay.log().skipped[0].find(path + ":"), std::string::npos);
  EXPECT_NE(replay.log().skipped[0].find("CRC mismatch"), std::string::npos);
  EXPECT_NE(replay.log().skipped[2].find("truncated"), std::string::npos);
  EXPECT_EQ(replay.scans_read(), 119u);
}

TEST(LogReplay, AnotherSensorEndsTheReadingAsBefore) {
  test::TestFolder dir;
  const std::string path = write_log(dir, 60, false, true);
  expect_streamed_equals_whole(path, 60, LiveClock::host);
  LogReplay replay(path, ScanMapperOptions{}, LiveClock::host);
  PoseTrack poses = poses_for(60);
  replay.run(poses);
  EXPECT_NE(replay.log().stop.find("parameters changed"), std::string::npos) << replay.log().stop;
  EXPECT_EQ(replay.scans_read(), 60u);
}

TEST(LogReplay, ALogWithoutSensorOrNotALogIsRefusedNamingTheFile) {
  test::TestFolder dir;
  const std::string not_log = dir.write("notes.txt", "hello\n");
  try {
    LogReplay replay(not_log, ScanMapperOptions{}, LiveClock::host);
    FAIL() << "not a log was read";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(not_log + ":1:"), std::string::npos) << e.what();
  }
  try {
    LogReplay replay(dir / "missing.txt", ScanMapperOptions{}, LiveClock::host);
    FAIL() << "a missing log was read";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("missing.txt: cannot open the scan log"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace stridemap
