// The library's live loop (live/live_mapping.hpp) driven directly, with a
// scripted scan source and pose source: it maps what arrives, saves
// periodically and at the end, survives a failing save (retried, mapping
// goes on), forwards faults and pose notices as events, ends on a stop
// request or another sensor, and applies the selected map filter.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <functional>
#include <chrono>
#include <deque>
#include <thread>
#include <utility>
#include <vector>

#include "live/running_emulator.hpp"
#include "live/test_folder.hpp"
#include "stridemap/core/error.hpp"
#include "stridemap/devices/serial_port.hpp"
#include "stridemap/live/live_mapping.hpp"

namespace stridemap {
namespace {

UrgScan make_scan(std::uint64_t k) {
  UrgScan s;
  s.sequence = k;
  s.sensor_time_ms = 100 * k;
  s.host_time_s = 1000.0 + 0.1 * static_cast<double>(k);
  s.host_receive_time_s = s.host_time_s;
  s.raw.first_step = 44;
  s.raw.cluster = 1;
  s.raw.time_s = s.host_time_s;
  s.raw.values_mm.assign(682, 450);  // the ground ahead of the default mount
  return s;
}

// Hands out a scripted list of events, one per call, then nothing.
class ScriptedScans final : public LiveScanSource {
 public:
  std::deque<UrgDriverEvent> events;
  scip::ScipParameters current;
  bool stopped = false;
  bool next(UrgDriverEvent& event, double timeout_s) override {
    if (events.empty()) {
      std::this_thread::sleep_for(std::chrono::duration<double>(std::min(timeout_s, 0.002)));
      return false;
    }
    event = events.front();
    events.pop_front();
    if (event.kind == UrgDriverEvent::Kind::scan) ++stats_.scans;
    if (event.kind == UrgDriverEvent::Kind::fault) ++stats_.faults;
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
    return true;
  }
  scip::ScipParameters parameters() const override { return current; }
  scip::VersionInfo version() const override { return {}; }
  UrgDriverStats stats() const override { return stats_; }
  void stop() override { stopped = true; }

 private:
  UrgDriverStats stats_;
};

class ScriptedPoses final : public LivePoseSource {
 public:
  std::vector<TimedPose> poses;
  std::vector<std::string> notices;
  std::size_t poll(PoseTrack& track) override {
    const std::size_t n = poses.size();
    for (const TimedPose& p : poses) track.append(p);
    poses.clear();
    return n;
  }
  std::vector<std::string> take_notices() override { return std::exchange(notices, {}); }
};

UrgDriverEvent scan_event(std::uint64_t k) {
  UrgDriverEvent e;
  e.kind = UrgDriverEvent::Kind::scan;
  e.scan = make_scan(k);
  return e;
}

LiveMappingOptions quick_options() {
  LiveMappingOptions o;
  o.clock = LiveClock::sensor;
  o.save_every_s = 0.01;
  o.save_retry_s = 0.005;
  o.status_every_s = 0.01;
  o.max_pose_gap_s = 100.0;
  return o;
}

ScriptedPoses poses_over(double from_s, double to_s) {
  ScriptedPoses poses;
  // Walking forward 0.2 m/s: the stripes of scans 0.1 s apart leave holes to fill.
  for (double t = from_s; t <= to_s + 1e-9; t += 0.5) {
    TrunkPose pose;
    pose.x_m = 0.2 * (t - from_s);
    poses.poses.push_back({t, pose});
  }
  return poses;
}

TEST(LiveMapping, MapsEveryScanSavesPeriodicallyAndAtTheEnd) {
  ScriptedScans scans;
  for (std::uint64_t k = 0; k < 30; ++k) scans.events.push_back(scan_event(k));
  ScriptedPoses poses = poses_over(0.0, 10.0);
  LiveMappingOptions options = quick_options();
  options.max_scans = 30;
  std::size_t periodic = 0, final_saves = 0, statuses = 0, recorded = 0;
  LiveMappingHooks hooks;
  hooks.save = [&](const ScanMapper&, const LiveRunStats* run) { ++(run ? final_saves : periodic); };
  hooks.on_event = [&](const LiveEvent& e) { statuses += e.kind == LiveEvent::Kind::status; };
  hooks.on_scan = [&](const UrgScan&) { ++recorded; };
  LiveMapping live(options, scans, poses, hooks);
  std::atomic<bool> stop{false};
  const LiveMappingResult result = live.run(stop);
  EXPECT_TRUE(result.fatal.empty()) << result.fatal;
  EXPECT_EQ(live.mapper().stats().integrated, 30u);
  EXPECT_EQ(recorded, 30u);
  EXPECT_EQ(final_saves, 1u);
  EXPECT_GT(periodic, 0u);
  EXPECT_GT(statuses, 0u);
  EXPECT_TRUE(scans.stopped);
  EXPECT_EQ(result.run.saves, periodic + 1);
  EXPECT_EQ(result.run.latency_samples, 30u);
  EXPECT_EQ(live.scan_times().count, 30u);
  EXPECT_DOUBLE_EQ(live.scan_times().last_s, 2.9);
  EXPECT_DOUBLE_EQ(live.pose_times().first_s, 0.0);
}

// Saving through a MapSaver: the loop writes the run's set itself, the last
// save with the run's figures, and the hook's save is not asked.
TEST(LiveMapping, SavesThroughAMapSaver) {
  test::TestFolder dir;
  ScriptedScans scans;
  for (std::uint64_t k = 0; k < 20; ++k) scans.events.push_back(scan_event(k));
  ScriptedPoses poses = poses_over(0.0, 10.0);
  LiveMappingOptions options = quick_options();
  options.max_scans = 20;
  MapRunInfo info;
  info.command = "live";
  info.scans_from = "/dev/ttyACM0";
  info.pose_lines_skipped = 7;  // brought up to date from the pose source at each save
  MapSaver saver(info, dir / "out");
  bool hook_asked = false;
  LiveMappingHooks hooks;
  hooks.save = [&](const ScanMapper&, const LiveRunStats*) { hook_asked = true; };
  LiveMapping live(options, scans, poses, saver, hooks);
  std::atomic<bool> stop{false};
  const LiveMappingResult result = live.run(stop);
  EXPECT_TRUE(result.last_save_error.empty()) << result.last_save_error;
  EXPECT_FALSE(hook_asked);
  EXPECT_GT(result.run.saves, 1u);
  EXPECT_EQ(saver.info().pose_lines_skipped, 0u);
  const std::string summary = dir.read("out/summary.json");
  EXPECT_NE(summary.find("\"latency_s\""), std::string::npos);
  EXPECT_NE(summary.find("\"command\": \"live\""), std::string::npos) << summary;
  EXPECT_NE(summary.find("\"pose_lines_skipped\": 0"), std::string::npos) << summary;
}

// Disk full: the save throws; it is reported, retried soon, and mapping goes
// on; once the disk has room again the map is saved and that is said too.
TEST(LiveMapping, FailedSaveIsReportedAndRetriedWhileMappingGoesOn) {
  ScriptedScans scans;
  for (std::uint64_t k = 0; k < 40; ++k) scans.events.push_back(scan_event(k));
  ScriptedPoses poses = poses_over(0.0, 10.0);
  LiveMappingOptions options = quick_options();
  options.max_scans = 40;
  int failures_left = 3;
  std::vector<LiveEvent::Kind> kinds;
  std::size_t mapped_while_failing = 0;
  const ScanMapper* seen = nullptr;
  LiveMappingHooks hooks;
  hooks.save = [&](const ScanMapper& mapper, const LiveRunStats*) {
    seen = &mapper;
    if (failures_left-- > 0) {
      mapped_while_failing = mapper.stats().integrated;
      throw InputError("out/elevation.png: write failed (No space left on device)");
    }
  };
  hooks.on_event = [&](const LiveEvent& e) {
    if (e.kind != LiveEvent::Kind::status) kinds.push_back(e.kind);
  };
  LiveMapping live(options, scans, poses, hooks);
  std::atomic<bool> stop{false};
  const LiveMappingResult result = live.run(stop);
  EXPECT_EQ(live.mapper().stats().integrated, 40u);  // mapping went on
  EXPECT_EQ(result.run.save_failures, 3u);
  EXPECT_TRUE(result.last_save_error.empty());
  ASSERT_GE(kinds.size(), 4u);
  EXPECT_EQ(kinds[0], LiveEvent::Kind::save_failed);
  EXPECT_EQ(kinds[3], LiveEvent::Kind::save_recovered);
  EXPECT_LT(mapped_while_failing, 40u);
  EXPECT_EQ(seen, &live.mapper());
}

TEST(LiveMapping, FinalSaveThatKeepsFailingIsInTheResult) {
  ScriptedScans scans;
  scans.events.push_back(scan_event(0));
  ScriptedPoses poses = poses_over(0.0, 10.0);
  LiveMappingOptions options = quick_options();
  options.max_scans = 1;
  options.save_every_s = 100.0;
  LiveMappingHooks hooks;
  hooks.save = [&](const ScanMapper&, const LiveRunStats*) { throw InputError("out: disk full"); };
  LiveMapping live(options, scans, poses, hooks);
  std::atomic<bool> stop{false};
  const LiveMappingResult result = live.run(stop);
  EXPECT_EQ(result.last_save_error, "out: disk full");
  EXPECT_EQ(result.run.save_failures, 3u);  // the last save is tried three times
}

TEST(LiveMapping, FaultsAndPoseNoticesAreEventsAndAnotherSensorEndsTheRun) {
  ScriptedScans scans;
  UrgDriverEvent fault;
  fault.kind = UrgDriverEvent::Kind::fault;
  fault.fault = UrgFault::stall;
  fault.message = "no scan for 0.5 s";
  scans.events.push_back(scan_event(0));
  scans.events.push_back(fault);
  scans.events.push_back(scan_event(1));
  UrgDriverEvent reconnected;
  reconnected.kind = UrgDriverEvent::Kind::connected;
  scans.events.push_back(reconnected);
  ScriptedPoses poses = poses_over(0.0, 10.0);
  poses.notices.push_back("poses.txt:7: field 2 'x' is not a finite number");
  std::vector<std::string> faults, notices;
  LiveMappingHooks hooks;
  hooks.on_event = [&](const LiveEvent& e) {
    if (e.kind == LiveEvent::Kind::fault) {
      ASSERT_NE(e.driver_event, nullptr);
      EXPECT_EQ(e.driver_event->fault, UrgFault::stall);
      faults.push_back(e.message);
    }
    if (e.kind == LiveEvent::Kind::pose_notice) notices.push_back(e.message);
    // The sensor that answers the reconnection is another one.
    if (e.kind == LiveEvent::Kind::fault) scans.current.last_step = 700;
  };
  bool saved = false;
  hooks.save = [&](const ScanMapper&, const LiveRunStats* run) { saved = saved || run != nullptr; };
  LiveMapping live(quick_options(), scans, poses, hooks);
  std::atomic<bool> stop{false};
  const LiveMappingResult result = live.run(stop);
  EXPECT_EQ(faults, std::vector<std::string>{"no scan for 0.5 s"});
  EXPECT_EQ(notices, std::vector<std::string>{"poses.txt:7: field 2 'x' is not a finite number"});
  EXPECT_NE(result.fatal.find("another sensor answered"), std::string::npos) << result.fatal;
  EXPECT_EQ(live.mapper().stats().integrated, 2u);  // the map up to then
  EXPECT_TRUE(saved);
}

TEST(LiveMapping, StopRequestEndsTheRunAndScansWithoutPosesAreCounted) {
  ScriptedScans scans;
  for (std::uint64_t k = 0; k < 10; ++k) scans.events.push_back(scan_event(k));
  ScriptedPoses poses = poses_over(100.0, 110.0);  // another clock: no scan has a pose
  LiveMappingOptions options = quick_options();
  std::atomic<bool> stop{false};
  LiveMappingHooks hooks;
  hooks.on_scan = [&](const UrgScan& scan) {
    if (scan.sequence == 9) stop.store(true);
  };
  LiveMapping live(options, scans, poses, hooks);
  live.run(stop);
  EXPECT_EQ(live.mapper().stats().scans, 10u);
  EXPECT_EQ(live.mapper().stats().integrated, 0u);
  EXPECT_EQ(live.mapper().stats().before_first_pose, 10u);
  const std::string why = mapping_shortfall(live.mapper().stats(), live.scan_times(), live.pose_times(), "sensor");
  EXPECT_NE(why.find("0 scans mapped of 10: the scans span 0.000 .. 0.900 s, the poses 100.000 .. 110.000 s "
                     "(sensor clock): they do not overlap"),
            std::string::npos)
      << why;
  EXPECT_NE(why.find("10 before the first pose"), std::string::npos) << why;
}

TEST(LiveMapping, OptionsAreCheckedAndTheMapFilterIsSelectable) {
  ScriptedScans scans;
  ScriptedPoses poses;
  for (const auto& bad : std::vector<std::function<void(LiveMappingOptions&)>>{
           [](LiveMappingOptions& o) { o.save_every_s = 0.0; },
           [](LiveMappingOptions& o) { o.pose_wait_s = -1.0; },
           [](LiveMappingOptions& o) { o.duration_s = -1.0; },
           [](LiveMappingOptions& o) { o.status_every_s = std::nan(""); }}) {
    LiveMappingOptions o = quick_options();
    bad(o);
    EXPECT_THROW(LiveMapping(o, scans, poses, {}), InputError);
  }
  for (std::uint64_t k = 0; k < 20; ++k) scans.events.push_back(scan_event(k));
  poses = poses_over(0.0, 10.0);
  LiveMappingOptions o = quick_options();
  o.max_scans = 20;
  LiveMapping live(o, scans, poses, {});
  std::atomic<bool> stop{false};
  live.run(stop);
  const ExportedMap none = filtered_map_layers(live.mapper(), MapFilter::none);
  const ExportedMap fill = filtered_map_layers(live.mapper(), MapFilter::fill);
  const ExportedMap cas = filtered_map_layers(live.mapper(), MapFilter::cas);
  EXPECT_GT(map_coverage(none), 0.0);
  EXPECT_GE(map_coverage(fill), map_coverage(none));
  const auto count_filled = [](const ExportedMap& l) {
    return (l.state().array() == static_cast<std::uint8_t>(CellState::filled)).count();
  };
  EXPECT_EQ(count_filled(none), 0);
  EXPECT_GT(count_filled(fill), 0);
  EXPECT_GT(count_filled(cas), 0);
}

// The loop on a real driver reading the emulator through a pseudo-terminal:
// the same scans and the same map as the simulation, the map saved through
// the hook as the tool saves it.
TEST(LiveMapping, RunsOnAUrgDriverReadingTheEmulator) {
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
  options.max_scans = 60;
  options.save_every_s = 0.5;
  options.pose_wait_s = 2.0;
  std::size_t saves = 0;
  LiveMappingHooks hooks;
  MapRunInfo info;
  info.command = "live";
  hooks.save = [&](const ScanMapper& mapper, const LiveRunStats* run) {
    ++saves;
    write_map_outputs(mapper, scans.parameters(), info, run, dir / "out");
  };
  LiveMapping live(options, scans, poses, hooks);
  std::atomic<bool> stop{false};
  const LiveMappingResult result = live.run(stop);
  EXPECT_TRUE(result.fatal.empty()) << result.fatal;
  EXPECT_TRUE(result.last_save_error.empty()) << result.last_save_error;
  EXPECT_EQ(live.mapper().stats().scans, 60u);
  EXPECT_GE(live.mapper().stats().integrated, 59u);  // the first scan may precede the first pose line read
  EXPECT_GT(map_coverage(filtered_map_layers(live.mapper(), MapFilter::fill)), 0.0);
  EXPECT_GT(result.run.latency_samples, 50u);
  EXPECT_GE(saves, 1u);
  EXPECT_NE(dir.read("out/summary.json").find("\"latency_s\""), std::string::npos);
}

}  // namespace
}  // namespace stridemap
