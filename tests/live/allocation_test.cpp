// Live mapping and log replay allocate nothing per scan once warmed up: the
// whole `live` loop (a real UrgDriver reading the URG emulator through a
// pseudo-terminal, the pose file read as a stream) and the whole
// `map --log` loop (the log read as a stream). Global operator new is
// replaced in this test binary and counts while a flag is set; in the live
// test only the mapping thread counts (the emulator simulates on its own).
#include <gtest/gtest.h>

#include "allocation_counting.hpp"

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "live/running_emulator.hpp"
#include "live/test_folder.hpp"
#include "stridemap/devices/serial_port.hpp"
#include "stridemap/live/live_mapping.hpp"
#include "stridemap/live/log_replay.hpp"
#include "stridemap/recordings/scan_log.hpp"
#include "stridemap/sensors/scip_decoder.hpp"
#include "stridemap/sensors/scip_reply_encoder.hpp"

STRIDEMAP_REPLACE_OPERATOR_NEW()

namespace stridemap {
namespace {

using test::allocation_counter;

constexpr double kScanPeriodS = 0.1;

// A log of `scans` scans of the ground ahead, every value changing from scan
// to scan, written as the recorder writes it.
void write_log(const std::string& path, std::size_t scans) {
  io::ScanLogWriter writer(path, "/dev/ttyACM0");
  const scip::VersionInfo version{"Hokuyo Automatic Co.,Ltd.", "SOKUIKI Sensor URG-04LX", "3.3.00", "SCIP 2.0", "H0"};
  writer.write_sensor(1000.0, version, scip::ScipParameters{});
  UrgScan s;
  s.raw.first_step = 44;
  s.raw.cluster = 1;
  s.raw.values_mm.resize(682);
  for (std::size_t k = 0; k < scans; ++k) {
    s.sequence = k;
    s.host_time_s = 1000.0 + kScanPeriodS * static_cast<double>(k);
    s.host_receive_time_s = s.host_time_s + 0.01;
    s.sensor_time_ms = 100 * k;
    s.sensor_timestamp_ms = static_cast<std::uint32_t>(s.sensor_time_ms);
    for (std::size_t i = 0; i < s.raw.values_mm.size(); ++i) {
      s.raw.values_mm[i] = 420 + static_cast<std::uint32_t>((k * 7 + i * 13) % 60);
    }
    writer.write_scan(s);
  }
}

PoseTrack walking_poses(std::size_t scans) {
  PoseTrack track(1.0);
  for (std::size_t k = 0; k <= 2 * scans + 2; ++k) {
    TimedPose p;
    p.time_s = 999.9 + 0.5 * kScanPeriodS * static_cast<double>(k);
    p.pose.x_m = 0.02 * static_cast<double>(k);  // 0.4 m/s: the window moves
    p.pose.yaw_rad = 0.001 * static_cast<double>(k);
    track.append(p);
  }
  return track;
}

TEST(ReplayAllocation, MapLogLoopAllocatesNothingPerScan) {
  STRIDEMAP_SKIP_UNLESS_COUNTING_ALLOCATIONS();
  test::TestFolder dir;
  constexpr std::size_t kScans = 1200, kWarmUp = 100;
  write_log(dir / "log.txt", kScans);
  PoseTrack poses = walking_poses(kScans);
  LogReplay replay(dir / "log.txt", ScanMapperOptions{}, LiveClock::host);
  for (std::size_t k = 0; k < kWarmUp; ++k) ASSERT_TRUE(replay.step(poses));
  allocation_counter().allocations = 0;
  allocation_counter().counting = true;
  std::size_t steps = 0;
  while (replay.step(poses)) ++steps;
  allocation_counter().counting = false;
  EXPECT_EQ(allocation_counter().allocations.load(), 0u) << "over " << steps << " scans";
  EXPECT_EQ(steps, kScans - kWarmUp);
  EXPECT_EQ(replay.scans_read(), kScans);
  EXPECT_GT(replay.mapper().stats().integrated, kScans - 5);
}

// Reads that end inside a line (a loaded host's driver gets the stream in
// smaller pieces) leave the line's start with the decoder until the rest
// comes: that allocated the first times it happened, failing the live loop's
// count below under load.
TEST(DecoderAllocation, FramesFedInPiecesThatSplitLinesAllocateNothing) {
  STRIDEMAP_SKIP_UNLESS_COUNTING_ALLOCATIONS();
  std::vector<std::uint32_t> values(682);
  for (std::size_t i = 0; i < values.size(); ++i) values[i] = 20 + static_cast<std::uint32_t>((i * 37) % 4000);
  std::string frame;
  scip::append_distance_frame("MD0044072501000", "99", 5, values, 3, frame);
  scip::Decoder decoder;
  scip::Event event;
  // One whole frame first: the event's own vectors get their room.
  decoder.feed(frame);
  while (decoder.next(event)) {
  }
  ASSERT_EQ(event.distance.values.size(), values.size());
  allocation_counter().allocations = 0;
  allocation_counter().counting = true;
  std::size_t frames = 0;
  for (const std::size_t piece : {7u, 13u, 64u, 67u, 101u}) {
    for (std::size_t at = 0; at < frame.size(); at += piece) {
      decoder.feed(std::string_view(frame).substr(at, piece));
      while (decoder.next(event)) {
        if (event.kind == scip::EventKind::distance) ++frames;
      }
    }
  }
  allocation_counter().counting = false;
  EXPECT_EQ(allocation_counter().allocations.load(), 0u);
  EXPECT_EQ(frames, 5u);
}

// The live loop as `stridemap live` runs it, counted between scan 150 and
// scan 550 (later should the loop report an event; the emulator sends 100
// per second). The periodic save and status line are due only after the
// run: they are not per scan.
TEST(LiveAllocation, LiveLoopOnTheEmulatorAllocatesNothingPerScan) {
  STRIDEMAP_SKIP_UNLESS_COUNTING_ALLOCATIONS();
  test::TestFolder dir;
  const test_emulator::Simulation sim;
  EmulatorServerOptions server;
  server.link_path = dir / "urg";
  server.poses_path = dir / "poses.txt";
  server.pose_clock = PoseClock::sensor;
  test_emulator::RunningEmulator emulator(sim, server);
  UrgDriver driver(io::SerialPort::opener(server.link_path));
  const UrgDriverEvent event = test_emulator::wait_until_connected(driver);
  ASSERT_EQ(event.kind, UrgDriverEvent::Kind::connected) << event.message;
  UrgDriverSource scans(driver);
  PoseStreamSource poses(server.poses_path);
  LiveMappingOptions options;
  options.clock = LiveClock::sensor;
  options.save_every_s = 3600.0;
  options.status_every_s = 3600.0;
  options.pose_wait_s = 2.0;
  options.duration_s = 60.0;  // a bound should the emulator stall; the scan count ends it
  constexpr std::uint64_t kWarmUp = 150, kCounted = 400, kRestartAfter = 50, kMaxEvents = 10;
  // An event (a driver fault, a pose line skipped, a clock warning: on a host
  // starved by a parallel build, or by the compiling tests and the waiting
  // lane `make test` starts beside this one, the emulator's pseudo-terminal
  // can overflow or a pose arrive late) is not a scan, and its message
  // allocates. So the count restarts, after a settling gap, once per event,
  // and the 400 counted scans must run without one.
  std::atomic<bool> stop{false};
  std::uint64_t seen = 0, events = 0, count_from = kWarmUp;
  std::vector<std::string> event_messages;
  event_messages.reserve(kMaxEvents + 1);
  LiveMappingHooks hooks;
  hooks.on_event = [&](const LiveEvent& e) {
    allocation_counter().counting = false;
    ++events;
    event_messages.push_back(e.message);
    count_from = seen + kRestartAfter;
    if (events > kMaxEvents) stop = true;
  };
  hooks.on_scan = [&](const UrgScan&) {
    ++seen;
    if (seen == count_from) {
      allocation_counter().only_thread = std::this_thread::get_id();
      allocation_counter().allocations = 0;
      allocation_counter().counting = true;
    } else if (seen == count_from + kCounted) {
      allocation_counter().counting = false;
      stop = true;
    }
  };
  LiveMapping live(options, scans, poses, hooks);
  const LiveMappingResult result = live.run(stop);
  allocation_counter().counting = false;
  allocation_counter().only_thread = std::thread::id{};
  EXPECT_TRUE(result.fatal.empty()) << result.fatal;
  std::string event_list;
  for (const std::string& m : event_messages) event_list += "\n  " + m;
  ASSERT_LE(events, kMaxEvents) << "events:" << event_list;
  ASSERT_GE(seen, count_from + kCounted) << "events:" << event_list;
  EXPECT_EQ(allocation_counter().allocations.load(), 0u)
      << "over " << kCounted << " scans from scan " << count_from << "; events:" << event_list;
  EXPECT_GT(live.mapper().stats().integrated, kWarmUp + kCounted - 50);
  EXPECT_GT(result.run.latency_samples, kWarmUp);
}

}  // namespace
}  // namespace stridemap
