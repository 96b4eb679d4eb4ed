// End to end on a real pseudo-terminal: the emulator in real time, the
// driver reading it through the serial transport. The scans arrive bit for
// bit as simulated, the map built from them equals the map built from the
// same simulation in memory, and every injected fault is reported and
// survived with every scan either delivered once or counted as lost.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstring>
#include <future>
#include <map>
#include <sstream>
#include <thread>

#include "live/running_emulator.hpp"
#include "live/test_folder.hpp"
#include "stridemap/config/scene_yaml.hpp"
#include "stridemap/devices/serial_port.hpp"
#include "stridemap/live/emulator_server.hpp"
#include "stridemap/live/scan_mapper.hpp"
#include "stridemap/sensors/urg_driver.hpp"
#include "stridemap/sim/urg_scan_source.hpp"

namespace stridemap {
namespace {

using test_emulator::kPeriodMs;
using test_emulator::kRateHz;
using test_emulator::kSeed;
using test_emulator::RunningEmulator;
using test_emulator::Simulation;

struct Collected {
  std::vector<UrgScan> scans;
  std::vector<UrgDriverEvent> faults;
  bool has(UrgFault f) const {
    for (const auto& e : faults) {
      if (e.fault == f) return true;
    }
    return false;
  }
  std::string list() const {
    std::string out;
    for (const auto& e : faults) out += std::string(fault_name(e.fault)) + ": " + e.message + "\n";
    return out;
  }
};

// Reads the driver until `enough` says so or `seconds` pass (a bound, never a wait).
template <typename Enough>
Collected collect(UrgDriver& driver, double seconds, Enough enough) {
  Collected c;
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  UrgDriverEvent e;
  while (std::chrono::steady_clock::now() < end && !enough(c)) {
    if (!driver.next(e, 0.05)) continue;
    if (e.kind == UrgDriverEvent::Kind::scan) c.scans.push_back(e.scan);
    if (e.kind == UrgDriverEvent::Kind::fault) c.faults.push_back(e);
  }
  return c;
}

TEST(EmulatorLink, ScansArriveAsSimulatedAndTheMapEqualsTheInMemoryOne) {
  test::TestFolder dir;
  const Simulation sim;
  EmulatorServerOptions server;
  server.link_path = dir / "urg";
  RunningEmulator emulator(sim, server);
  UrgDriver driver(io::SerialPort::opener(server.link_path));
  const Collected got = collect(driver, 20.0, [](const Collected& c) { return c.scans.size() >= 60; });
  ASSERT_GE(got.scans.size(), 60u) << got.list();
  EXPECT_TRUE(got.faults.empty()) << got.list();
  EXPECT_EQ(driver.parameters().motor_speed_rpm, kRateHz * 60);

  // Live: what the driver delivered, at the poses of the sensor's clock.
  ScanMapper live({}, driver.urg_parameters());
  PoseTrack poses;
  // In memory: the same scans simulated here, straight into a mapper.
  const auto reference_source = sim.make_source();
  UrgModel model(sim.urg);
  TerrainMapper reference(MapperOptions{}, SensorMount{});
  UrgRawScan raw;
  PlanarScan planar;
  std::vector<std::uint32_t> values;
  for (const UrgScan& scan : got.scans) {
    ASSERT_EQ(scan.sensor_time_ms % kPeriodMs, 0u);
    const std::uint64_t n = scan.sensor_time_ms / kPeriodMs;  // the scan's number since power-up
    const double world_s = static_cast<double>(static_cast<std::int64_t>(n) * kPeriodMs) * 1e-3;
    reference_source->scan(n, world_s, values);
    ASSERT_EQ(scan.raw.values_mm, values) << "scan " << n << " changed on its way";

    const TrunkPose pose = sim.motion->pose_at(world_s);
    poses.append({sensor_time_seconds(scan.sensor_time_ms), pose});
    UrgRawScan timed = scan.raw;
    timed.time_s = sensor_time_seconds(scan.sensor_time_ms);
    live.add(timed);
    live.process(poses, false);

    raw.time_s = timed.time_s;
    raw.first_step = 44;
    raw.values_mm = values;
    model.to_planar_scan(raw, planar);
    reference.integrate(planar, pose);
  }
  live.finish();
  EXPECT_EQ(live.stats().integrated, got.scans.size());
  const ExportedMap a = export_map(live.map());
  const ExportedMap b = export_map(reference.map());
  ASSERT_EQ(a.elevation_m().size(), b.elevation_m().size());
  EXPECT_EQ(std::memcmp(a.elevation_m().data(), b.elevation_m().data(), sizeof(float) * a.elevation_m().size()), 0);
  EXPECT_EQ(std::memcmp(a.certainty().data(), b.certainty().data(), sizeof(float) * a.certainty().size()), 0);
  EXPECT_EQ(a.state(), b.state());
  EXPECT_EQ(a.min_cell, b.min_cell);
  EXPECT_GT(map_coverage(a), 0.3);  // the map is not trivially empty
}

// One line of the emulator's trace.
struct TracedFrame {
  int epoch = 0;  ///< counts the sensor's restarts (reset, reconnect)
  std::uint32_t ts = 0;
  std::string fate;
};

std::vector<TracedFrame> read_trace(const std::string& text) {
  std::vector<TracedFrame> frames;
  std::istringstream in(text);
  std::string line;
  int epoch = 0;
  while (std::getline(in, line)) {
    if (line.find(" reset") != std::string::npos || line.find(" reconnect ") != std::string::npos) ++epoch;
    if (line.find(" frame ") == std::string::npos) continue;
    TracedFrame f;
    f.epoch = epoch;
    f.ts = static_cast<std::uint32_t>(std::stoul(line.substr(line.find(" ts=") + 4)));
    f.fate = line.substr(line.find(" fate=") + 6);
    if (f.fate == "reset") {
      f.epoch = epoch - 1;  // the reset line comes just before: the frame belonged to the old clock
    }
    frames.push_back(f);
  }
  return frames;
}

TEST(EmulatorLink, EveryInjectedFaultIsReportedAndNoScanIsSilentlyLost) {
  test::TestFolder dir;
  const Simulation sim;
  EmulatorServerOptions server;
  server.link_path = dir / "urg";
  server.trace_path = dir / "trace.txt";
  server.faults = {parse_emulator_fault("corrupt@10"), parse_emulator_fault("drop@20"),
                   parse_emulator_fault("drop@21"), parse_emulator_fault("stall@30:0.8"),
                   parse_emulator_fault("reset@60"), parse_emulator_fault("disconnect@90:0.6")};
  std::vector<UrgScan> scans;
  Collected got;
  {
    RunningEmulator emulator(sim, server);
    UrgDriver driver(io::SerialPort::opener(server.link_path));
    got = collect(driver, 30.0, [](const Collected& c) {
      int epochs = 0;
      std::size_t in_last = 0;
      for (const UrgScan& s : c.scans) {
        if (s.first_after_start) {
          ++epochs;
          in_last = 0;
        }
        ++in_last;
      }
      return epochs == 3 && in_last >= 30;  // through all faults and well into the last stretch
    });
  }
  const std::vector<TracedFrame> frames = read_trace(dir.read("trace.txt"));
  ASSERT_FALSE(got.scans.empty()) << got.list();
  EXPECT_TRUE(got.has(UrgFault::corrupt_data)) << got.list();
  EXPECT_TRUE(got.has(UrgFault::scans_lost)) << got.list();
  EXPECT_TRUE(got.has(UrgFault::stall)) << got.list();
  EXPECT_TRUE(got.has(UrgFault::sensor_reset)) << got.list();
  EXPECT_TRUE(got.has(UrgFault::link_lost)) << got.list();

  // Split the delivered scans where the driver says the clock restarted.
  std::vector<std::vector<UrgScan>> epochs;
  for (const UrgScan& s : got.scans) {
    if (s.first_after_start) epochs.emplace_back();
    ASSERT_FALSE(epochs.empty());
    epochs.back().push_back(s);
  }
  ASSERT_EQ(epochs.size(), 3u) << got.list();  // start, after the reset, after the reconnection
  for (std::size_t e = 0; e < epochs.size(); ++e) {
    SCOPED_TRACE("epoch " + std::to_string(e));
    const std::vector<UrgScan>& delivered = epochs[e];
    std::map<std::uint32_t, std::string> fate_of;
    for (const TracedFrame& f : frames) {
      if (f.epoch == static_cast<int>(e)) fate_of[f.ts] = f.fate;
    }
    // Each delivered scan was sent intact, once; each gap is counted.
    std::uint64_t lost = 0;
    for (std::size_t i = 0; i < delivered.size(); ++i) {
      const UrgScan& s = delivered[i];
      EXPECT_EQ(fate_of[s.sensor_timestamp_ms], "sent") << "ts " << s.sensor_timestamp_ms;
      if (i == 0) continue;
      ASSERT_GT(s.sensor_timestamp_ms, delivered[i - 1].sensor_timestamp_ms) << "repeated or out of order";
      const std::uint64_t periods = (s.sensor_timestamp_ms - delivered[i - 1].sensor_timestamp_ms) / kPeriodMs;
      EXPECT_EQ(s.lost_before, periods - 1) << "ts " << s.sensor_timestamp_ms;
      lost += s.lost_before;
    }
    const std::uint32_t first = delivered.front().sensor_timestamp_ms, last = delivered.back().sensor_timestamp_ms;
    EXPECT_EQ(delivered.size() + lost, (last - first) / kPeriodMs + 1);
    // Frames sent intact but not delivered (sent while the driver restarted
    // the stream, and ignored as stale) lie inside the counted gaps.
    std::size_t undelivered = 0;
    for (const auto& [ts, fate] : fate_of) {
      if (ts < first || ts > last || fate != "sent") continue;
      bool found = false;
      for (const UrgScan& s : delivered) found = found || s.sensor_timestamp_ms == ts;
      undelivered += found ? 0 : 1;
    }
    EXPECT_LE(undelivered, lost);
  }
}

}  // namespace
}  // namespace stridemap
