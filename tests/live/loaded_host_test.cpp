// The driver on a host with every core busy: busy threads (several per
// core) compete with the emulator and the driver for the CPU, so the driver
// often reads late and finds several scans waiting. That is not a sensor
// fault: no sensor_reset, no stall, no restart may be reported, and every
// scan the emulator sent must be delivered, once, in order. (Scans the
// emulator could not send because the host left its buffer full are lost
// as on a real unit, and must be counted as lost, exactly.)
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "live/running_emulator.hpp"
#include "live/test_folder.hpp"
#include "stridemap/devices/serial_port.hpp"
#include "stridemap/sensors/urg_driver.hpp"

namespace stridemap {
namespace {

// The emulator stands for the sensor, which a busy host does not slow
// down: the busy threads and the driver's thread run at a lower priority
// than the emulator's, equal to each other (Linux's nice is per thread;
// raising it needs no privilege).
void lower_this_threads_priority() {
  setpriority(PRIO_PROCESS, static_cast<id_t>(syscall(SYS_gettid)), 10);
}

// Threads that keep every core busy until destroyed.
class BusyHost {
 public:
  explicit BusyHost(unsigned per_core) {
    const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
    for (unsigned k = 0; k < per_core * cores; ++k) {
      threads_.emplace_back([this] {
        lower_this_threads_priority();
        std::uint64_t spins = 0;
        while (!stop_.load(std::memory_order_relaxed)) ++spins;
        sink_.fetch_add(spins, std::memory_order_relaxed);
      });
    }
  }
  ~BusyHost() {
    stop_.store(true);
    for (std::thread& t : threads_) t.join();
  }

 private:
  std::atomic<bool> stop_{false};
  std::atomic<std::uint64_t> sink_{0};
  std::vector<std::thread> threads_;
};

// Each frame of the emulator's trace: its sensor timestamp and fate ("sent"
// intact, or "overflow": the host read so late that the sensor's buffer was
// full, so it was never sent, as a real unit drops it).
struct Frame {
  std::uint32_t ts = 0;
  std::string fate;
};
std::vector<Frame> traced_frames(const std::string& trace) {
  std::vector<Frame> frames;
  std::istringstream in(trace);
  std::string line;
  while (std::getline(in, line)) {
    const std::size_t ts = line.find(" ts="), fate = line.find(" fate=");
    if (line.find(" frame ") == std::string::npos || ts == std::string::npos || fate == std::string::npos) continue;
    frames.push_back({static_cast<std::uint32_t>(std::stoul(line.substr(ts + 4))), line.substr(fate + 6)});
  }
  return frames;
}

TEST(LoadedHost, NoFalseFaultAndNoScanLostWithEveryCoreBusy) {
  test::TestFolder dir;
  const test_emulator::Simulation sim;
  EmulatorServerOptions server;
  server.link_path = dir / "urg";
  server.trace_path = dir / "trace.txt";
  std::vector<UrgScan> scans;
  std::vector<UrgDriverEvent> faults;
  {
    test_emulator::RunningEmulator emulator(sim, server);
    UrgDriver driver(io::SerialPort::opener(server.link_path));
    BusyHost busy(12);  // a load average of about 12 per core
    std::thread reader([&] {
      lower_this_threads_priority();
      const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(3);
      UrgDriverEvent e;
      while (std::chrono::steady_clock::now() < end) {
        if (!driver.next(e, 0.05)) continue;
        if (e.kind == UrgDriverEvent::Kind::scan) scans.push_back(e.scan);
        if (e.kind == UrgDriverEvent::Kind::fault) faults.push_back(e);
      }
    });
    reader.join();
  }
  std::string fault_list;
  std::uint64_t reported_lost = 0;
  for (const UrgDriverEvent& f : faults) {
    fault_list += std::string(fault_name(f.fault)) + ": " + f.message + "\n";
    if (f.fault == UrgFault::scans_lost) reported_lost += f.count;
  }
  ASSERT_GE(scans.size(), 20u) << fault_list;

  // Every frame sent up to the last one delivered arrived, once, in order
  // (the ones after it were still on their way when the test stopped); the
  // only fault is scans_lost, for exactly the frames that were never sent.
  std::vector<std::uint32_t> expected;
  std::uint64_t not_sent = 0;
  for (const Frame& f : traced_frames(dir.read("trace.txt"))) {
    if (f.ts < scans.front().sensor_timestamp_ms || f.ts > scans.back().sensor_timestamp_ms) continue;
    EXPECT_TRUE(f.fate == "sent" || f.fate == "overflow") << "ts " << f.ts << " " << f.fate;
    if (f.fate == "sent") expected.push_back(f.ts);
    not_sent += f.fate == "sent" ? 0 : 1;
  }
  std::vector<std::uint32_t> delivered;
  std::uint64_t lost_before = 0;
  for (const UrgScan& s : scans) {
    delivered.push_back(s.sensor_timestamp_ms);
    lost_before += s.lost_before;
    EXPECT_FALSE(s.first_after_start && &s != &scans.front()) << "a restart at ts " << s.sensor_timestamp_ms;
  }
  EXPECT_EQ(delivered, expected);
  EXPECT_EQ(lost_before, not_sent);
  EXPECT_EQ(reported_lost, not_sent) << fault_list;
  for (const UrgDriverEvent& f : faults) EXPECT_EQ(f.fault, UrgFault::scans_lost) << fault_list;
}

}  // namespace
}  // namespace stridemap
