// The driver against the emulator on a virtual clock: start-up of both
// URG-04LX variants, scans and their times, and every fault reported and
// survived, with no scan lost or duplicated without a word.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "emulated_stream.hpp"
#include "stridemap/core/error.hpp"
#include "stridemap/sensors/scip_reply_encoder.hpp"
#include "stridemap/sensors/urg_driver.hpp"

namespace stridemap {
namespace {

using test::EmulatedDevice;
using test::VirtualClock;

// Scan k holds the value 1000 + (k mod 1000) at every step, so a scan's
// origin can be read from its values.
class CountingSource final : public UrgScanSource {
 public:
  void scan(std::uint64_t index, double, std::vector<std::uint32_t>& values) override {
    values.assign(682, static_cast<std::uint32_t>(1000 + index % 1000));
  }
};

struct Events {
  std::vector<UrgScan> scans;
  std::vector<UrgDriverEvent> faults;
  int connects = 0;
  bool has_fault(UrgFault f) const {
    for (const auto& e : faults) {
      if (e.fault == f) return true;
    }
    return false;
  }
  std::string fault_list() const {
    std::string out;
    for (const auto& e : faults) out += std::string(fault_name(e.fault)) + ": " + e.message + "\n";
    return out;
  }
};

class DriverFixture : public ::testing::Test {
 protected:
  UrgDriverOptions options() {
    UrgDriverOptions o;
    o.monotonic_clock = [this] { return clock_.seconds(); };
    o.host_clock = [this] { return 1.0e9 + clock_.seconds(); };
    o.sleep = [this](double s) { clock_.now_ms += static_cast<std::int64_t>(std::ceil(s * 1000.0)); };
    return o;
  }
  void make_device(UrgVariant variant = UrgVariant::classic, std::uint32_t timestamp_start = 0) {
    UrgEmulatorOptions o;
    o.variant = variant;
    o.timestamp_start_ms = timestamp_start;
    device_ = std::make_unique<EmulatedDevice>(o, source_, clock_);
  }
  // Runs the driver for `seconds` of virtual time, collecting events.
  Events run(UrgDriver& driver, double seconds) {
    Events events;
    const double end = clock_.seconds() + seconds;
    UrgDriverEvent e;
    while (clock_.seconds() < end) {
      const double before = clock_.seconds();
      if (driver.next(e, 0.2)) {
        if (e.kind == UrgDriverEvent::Kind::scan) events.scans.push_back(e.scan);
        if (e.kind == UrgDriverEvent::Kind::fault) events.faults.push_back(e);
        if (e.kind == UrgDriverEvent::Kind::connected) ++events.connects;
      }
      EXPECT_LE(clock_.seconds() - before, 0.2 + options().reply_timeout_s + 0.01) << "next() overran its timeout";
    }
    return events;
  }
  // Scans delivered in order: timestamps strictly increasing and each gap
  // accounted for by lost_before, within each stretch of a continuous clock.
  static void expect_accounted(const Events& events, std::int64_t period_ms) {
    for (std::size_t i = 1; i < events.scans.size(); ++i) {
      const UrgScan& a = events.scans[i - 1];
      const UrgScan& b = events.scans[i];
      EXPECT_EQ(b.sequence, a.sequence + 1);
      if (b.first_after_start) continue;
      ASSERT_GT(b.sensor_time_ms, a.sensor_time_ms) << "scan " << b.sequence << " repeats or goes back";
      const auto periods = static_cast<std::uint64_t>((b.sensor_time_ms - a.sensor_time_ms) / period_ms);
      EXPECT_EQ(b.lost_before, periods - 1) << "scan " << b.sequence;
    }
  }

  VirtualClock clock_;
  CountingSource source_;
  std::unique_ptr<EmulatedDevice> device_;
};

TEST_F(DriverFixture, StartsAClassicUrgFromScip11AndStreams) {
  make_device(UrgVariant::classic);
  UrgDriver driver(test::emulated_opener(*device_), options());
  const Events events = run(driver, 2.0);
  EXPECT_EQ(events.connects, 1);
  EXPECT_TRUE(events.faults.empty()) << events.fault_list();
  ASSERT_GE(events.scans.size(), 15u);
  EXPECT_EQ(driver.state(), UrgDriverState::streaming);
  EXPECT_EQ(driver.version().product, "SOKUIKI Sensor URG-04LX");
  EXPECT_EQ(driver.urg_parameters().first_step, 44);
  EXPECT_EQ(driver.urg_parameters().last_step, 725);
  EXPECT_TRUE(device_->emulator.scip2());
  EXPECT_TRUE(events.scans.front().first_after_start);
  for (const UrgScan& s : events.scans) {
    EXPECT_EQ(s.raw.first_step, 44);
    EXPECT_EQ(s.raw.values_mm.size(), 682u);
    EXPECT_EQ(s.sensor_time_ms % 100, 0u);  // one scan per 100 ms turn
    EXPECT_DOUBLE_EQ(s.raw.time_s, s.host_time_s);
    // Each value tells the scan's number, which the timestamp tells too.
    EXPECT_EQ(s.raw.values_mm[0], 1000 + s.sensor_time_ms / 100);
  }
  expect_accounted(events, 100);
  // Host time of step 0: the fake link has no delay, so the estimate is the
  // sensor time on the host clock exactly, one turn before the frame arrives.
  const UrgScan& last = events.scans.back();
  EXPECT_NEAR(last.host_receive_time_s - last.host_time_s, 0.1, 1e-6);
}

TEST_F(DriverFixture, StartsAUg01ThatSpeaksScip2FromPowerUp) {
  make_device(UrgVariant::ug01);
  UrgDriverOptions o = options();
  o.start_step = 100;
  o.end_step = 699;
  o.cluster = 3;
  UrgDriver driver(test::emulated_opener(*device_), o);
  const Events events = run(driver, 1.0);
  EXPECT_EQ(events.connects, 1);
  EXPECT_TRUE(events.faults.empty()) << events.fault_list();
  ASSERT_FALSE(events.scans.empty());
  EXPECT_EQ(events.scans[0].raw.first_step, 100);
  EXPECT_EQ(events.scans[0].raw.cluster, 3);
  EXPECT_EQ(events.scans[0].raw.values_mm.size(), 200u);
  EXPECT_EQ(driver.version().firmware, "3.4.03(17/Dec./2012)");
}

TEST_F(DriverFixture, StepsOutsideTheSensorsRangeAreRefusedWithTheRange) {
  make_device();
  UrgDriverOptions o = options();
  o.end_step = 760;
  UrgDriver driver(test::emulated_opener(*device_), o);
  const Events events = run(driver, 1.0);
  ASSERT_TRUE(events.has_fault(UrgFault::bad_reply)) << events.fault_list();
  EXPECT_NE(events.faults[0].message.find("44..725"), std::string::npos) << events.faults[0].message;
  EXPECT_TRUE(events.scans.empty());
}

TEST_F(DriverFixture, TimestampWrapKeepsTimeIncreasingWithoutLostScans) {
  make_device(UrgVariant::classic, (1u << 24) - 1500);
  UrgDriver driver(test::emulated_opener(*device_), options());
  const Events events = run(driver, 3.0);
  ASSERT_GE(events.scans.size(), 20u);
  EXPECT_TRUE(events.faults.empty()) << events.fault_list();
  EXPECT_LT(events.scans.back().sensor_timestamp_ms, events.scans.front().sensor_timestamp_ms);  // it wrapped
  expect_accounted(events, 100);
  EXPECT_EQ(driver.stats().scans_lost, 0u);
}

TEST_F(DriverFixture, DroppedAndCorruptedFramesAreReportedAndCounted) {
  make_device();
  int frame = 0;
  std::vector<std::uint32_t> intact;
  device_->on_output = [&frame, &intact](EmulatorOutput& out) {
    if (!out.is_scan) return;
    ++frame;
    if (frame == 5) {
      out.bytes.clear();  // dropped on the wire
    } else if (frame == 9) {
      out.bytes[out.bytes.size() / 2] ^= 0x01;  // one bit flipped
    } else if (frame == 12) {
      out.bytes = out.bytes.substr(0, 700);  // cut short
    } else {
      intact.push_back(out.timestamp_ms);
    }
  };
  UrgDriver driver(test::emulated_opener(*device_), options());
  const Events events = run(driver, 2.5);
  EXPECT_TRUE(events.has_fault(UrgFault::scans_lost)) << events.fault_list();
  EXPECT_TRUE(events.has_fault(UrgFault::corrupt_data)) << events.fault_list();
  EXPECT_EQ(driver.stats().scans_lost, 3u);
  expect_accounted(events, 100);
  // Every intact frame on the wire arrived once, and nothing else did.
  std::vector<std::uint32_t> got;
  for (const UrgScan& s : events.scans) got.push_back(s.sensor_timestamp_ms);
  ASSERT_LE(got.size(), intact.size());
  intact.resize(got.size());  // the last frames may still be on their way
  EXPECT_EQ(got, intact);
}

TEST_F(DriverFixture, DuplicateFrameIsDroppedAndReported) {
  make_device();
  int frame = 0;
  device_->on_output = [&frame](EmulatorOutput& out) {
    if (out.is_scan && ++frame == 4) out.bytes += out.bytes;
  };
  UrgDriver driver(test::emulated_opener(*device_), options());
  const Events events = run(driver, 1.5);
  EXPECT_TRUE(events.has_fault(UrgFault::duplicate_scan)) << events.fault_list();
  expect_accounted(events, 100);
}

TEST_F(DriverFixture, StallIsReportedAndTheStreamRestartsCountingTheMissedScans) {
  make_device();
  UrgDriver driver(test::emulated_opener(*device_), options());
  Events events = run(driver, 1.0);
  ASSERT_FALSE(events.scans.empty());
  device_->silent = true;  // the sensor hangs for 2 s, its clock running on
  Events during = run(driver, 2.0);
  device_->silent = false;
  Events after = run(driver, 6.0);
  EXPECT_TRUE(during.has_fault(UrgFault::stall)) << during.fault_list();
  ASSERT_FALSE(after.scans.empty()) << after.fault_list();
  EXPECT_FALSE(after.scans.front().first_after_start);  // the clock went on: the gap is counted
  EXPECT_GE(after.scans.front().lost_before, 15u);
  events.scans.insert(events.scans.end(), after.scans.begin(), after.scans.end());
  expect_accounted(events, 100);
}

TEST_F(DriverFixture, AHostThatReadsLateLosesNothingAndReportsNoFault) {
  make_device();
  UrgDriver driver(test::emulated_opener(*device_), options());
  Events events = run(driver, 1.0);
  ASSERT_FALSE(events.scans.empty());
  // The host was busy for 1.5 s (a loaded machine): the driver did not run
  // while the sensor went on sending. The scans wait in the port; the stall
  // deadline and the host-time step of the next scan both look like faults
  // until that input is read.
  clock_.now_ms += 1500;
  const Events after = run(driver, 1.0);
  EXPECT_TRUE(after.faults.empty()) << after.fault_list();
  ASSERT_FALSE(after.scans.empty());
  EXPECT_FALSE(after.scans.front().first_after_start);
  events.scans.insert(events.scans.end(), after.scans.begin(), after.scans.end());
  expect_accounted(events, 100);
  std::vector<std::uint32_t> sent, delivered;
  for (const EmulatorOutput& out : device_->sent_scans) {
    if (out.timestamp_ms <= events.scans.back().sensor_timestamp_ms) sent.push_back(out.timestamp_ms);
  }
  for (const UrgScan& s : events.scans) delivered.push_back(s.sensor_timestamp_ms);
  EXPECT_EQ(delivered, sent);
  EXPECT_EQ(driver.stats().scans_lost, 0u);
  EXPECT_EQ(driver.stats().resets, 0u);
  EXPECT_EQ(driver.stats().stalls, 0u);
}

TEST_F(DriverFixture, SensorResetIsDetectedFromItsClockAndFromScip11) {
  make_device();
  UrgDriver driver(test::emulated_opener(*device_), options());
  Events events = run(driver, 2.0);
  ASSERT_GE(events.scans.size(), 10u);
  device_->emulator.power_cycle(clock_.now_ms);  // watchdog restart on a live link
  Events after = run(driver, 5.0);
  EXPECT_TRUE(after.has_fault(UrgFault::stall) || after.has_fault(UrgFault::sensor_reset)) << after.fault_list();
  EXPECT_TRUE(after.has_fault(UrgFault::sensor_reset)) << after.fault_list();
  ASSERT_FALSE(after.scans.empty());
  EXPECT_TRUE(after.scans.front().first_after_start);
  EXPECT_EQ(driver.stats().resets, 1u);
  events.scans.insert(events.scans.end(), after.scans.begin(), after.scans.end());
  expect_accounted(events, 100);
}

TEST_F(DriverFixture, UnpluggedDeviceIsReportedOnceAndReopenedWhenItReturns) {
  make_device();
  UrgDriver driver(test::emulated_opener(*device_), options());
  Events events = run(driver, 1.0);
  ASSERT_FALSE(events.scans.empty());
  device_->present = false;
  Events gone = run(driver, 3.0);
  EXPECT_TRUE(gone.has_fault(UrgFault::link_lost)) << gone.fault_list();
  std::size_t open_failures = 0;
  for (const auto& f : gone.faults) open_failures += f.fault == UrgFault::open_failed;
  EXPECT_EQ(open_failures, 1u) << gone.fault_list();  // reported once per outage, not per retry
  EXPECT_EQ(driver.state(), UrgDriverState::disconnected);
  device_->present = true;
  device_->emulator.power_cycle(clock_.now_ms);  // USB power came back: SCIP 1.1 again
  Events back = run(driver, 3.0);
  EXPECT_EQ(back.connects, 1);
  ASSERT_FALSE(back.scans.empty()) << back.fault_list();
  EXPECT_TRUE(back.has_fault(UrgFault::sensor_reset)) << back.fault_list();
  EXPECT_TRUE(back.scans.front().first_after_start);
}

TEST_F(DriverFixture, ScansMissedWhileUnpluggedCountAsLost) {
  make_device();
  UrgDriver driver(test::emulated_opener(*device_), options());
  Events events = run(driver, 1.0);
  ASSERT_FALSE(events.scans.empty());
  const std::uint64_t lost_before = driver.stats().scans_lost;
  device_->present = false;
  run(driver, 2.0);
  device_->present = true;
  device_->emulator.power_cycle(clock_.now_ms);
  Events back = run(driver, 3.0);
  ASSERT_FALSE(back.scans.empty()) << back.fault_list();
  // From the last scan before the outage to the first after it, one every
  // 100 ms: the ones in between never arrived.
  const double gap_s = back.scans.front().host_receive_time_s - events.scans.back().host_receive_time_s;
  const auto expected = static_cast<std::uint64_t>(std::floor(gap_s / 0.1 + 0.5)) - 1;
  EXPECT_GE(gap_s, 2.0);
  EXPECT_EQ(driver.stats().scans_lost - lost_before, expected) << back.fault_list();
  EXPECT_EQ(driver.stats().scans_lost_by_host_time, expected);
  EXPECT_GE(expected, 20u);  // 2 s unplugged plus the reconnect at 10 scans/s
  std::uint64_t reported = 0;
  for (const auto& f : back.faults) {
    if (f.fault == UrgFault::sensor_reset) reported += f.count;
  }
  EXPECT_EQ(reported, expected);
}

TEST_F(DriverFixture, MissingDeviceIsReportedAndNextReturnsInTime) {
  make_device();
  device_->present = false;
  UrgDriver driver(test::emulated_opener(*device_), options());
  UrgDriverEvent e;
  ASSERT_TRUE(driver.next(e, 0.1));
  EXPECT_EQ(e.kind, UrgDriverEvent::Kind::fault);
  EXPECT_EQ(e.fault, UrgFault::open_failed);
  EXPECT_NE(e.message.find("No such file"), std::string::npos);
  const double before = clock_.seconds();
  EXPECT_FALSE(driver.next(e, 0.3));
  EXPECT_NEAR(clock_.seconds() - before, 0.3, 0.002);
}

TEST_F(DriverFixture, SilentDeviceIsNoUrg) {
  make_device();
  device_->silent = true;
  UrgDriver driver(test::emulated_opener(*device_), options());
  const Events events = run(driver, 4.0);
  ASSERT_TRUE(events.has_fault(UrgFault::no_reply)) << events.fault_list();
  EXPECT_NE(events.faults[0].message.find("no reply to QT"), std::string::npos) << events.faults[0].message;
  EXPECT_NE(events.faults[0].message.find("3 tries"), std::string::npos) << events.faults[0].message;
}

TEST_F(DriverFixture, DeviceThatSendsGarbageIsNoUrgAndTheMessageSaysWhatItSent) {
  make_device();
  device_->answer_with = "AT+GMR\r\nOK\r\n\xff\xfe garbage\n";  // a modem, say
  UrgDriver driver(test::emulated_opener(*device_), options());
  const Events events = run(driver, 4.0);
  ASSERT_TRUE(events.has_fault(UrgFault::no_reply)) << events.fault_list();
  EXPECT_NE(events.faults[0].message.find("none of them a SCIP 2.0 reply"), std::string::npos)
      << events.faults[0].message;
}

TEST_F(DriverFixture, StaleStreamFromAnEarlierSessionIsStoppedFirst) {
  make_device(UrgVariant::ug01);
  device_->emulator.receive("MD0044072501000\n", 0);  // another program left it streaming
  clock_.now_ms = 1000;
  device_->pump();
  UrgDriver driver(test::emulated_opener(*device_), options());
  const Events events = run(driver, 1.5);
  EXPECT_EQ(events.connects, 1);
  EXPECT_FALSE(events.scans.empty());
  expect_accounted(events, 100);
}

TEST_F(DriverFixture, LostStreamAcknowledgementDoesNotStopTheStart) {
  make_device();
  device_->on_output = [](EmulatorOutput& out) {
    if (out.bytes.rfind("MD0044072501000\n00P", 0) == 0) out.bytes[17] = 'X';  // the ack arrives damaged
  };
  UrgDriver driver(test::emulated_opener(*device_), options());
  const Events events = run(driver, 1.5);
  EXPECT_EQ(events.connects, 1);
  ASSERT_GE(events.scans.size(), 10u) << events.fault_list();
  EXPECT_EQ(events.scans.front().sensor_time_ms, 0u);  // the first scan of the stream is not lost either
  EXPECT_EQ(driver.stats().connects, 1u);
}

TEST_F(DriverFixture, SensorLeftInTimeAdjustModeIsTakenOutOfIt) {
  make_device(UrgVariant::ug01);
  device_->emulator.receive("TM0\n", 0);  // another program was synchronising clocks
  device_->emulator.output().clear();
  UrgDriver driver(test::emulated_opener(*device_), options());
  const Events events = run(driver, 1.5);
  EXPECT_EQ(events.connects, 1);
  EXPECT_TRUE(events.faults.empty()) << events.fault_list();
  EXPECT_FALSE(events.scans.empty());
}

TEST_F(DriverFixture, HardwareErrorStatusInTheStreamIsReported) {
  make_device();
  int frame = 0;
  device_->on_output = [&frame](EmulatorOutput& out) {
    if (out.is_scan && ++frame == 3) {
      out.bytes.clear();
      scip::append_status_reply("MD0044072501000", "50", out.bytes);  // laser trouble
    }
  };
  UrgDriver driver(test::emulated_opener(*device_), options());
  const Events events = run(driver, 1.5);
  ASSERT_TRUE(events.has_fault(UrgFault::sensor_error)) << events.fault_list();
  EXPECT_NE(events.fault_list().find("hardware trouble"), std::string::npos) << events.fault_list();
}

TEST_F(DriverFixture, RandomGarbageOnTheWireNeverLosesAScanSilently) {
  make_device();
  std::mt19937_64 rng(3);
  std::size_t damaged = 0;
  device_->on_output = [&](EmulatorOutput& out) {
    if (!out.is_scan) return;
    switch (rng() % 6) {
      case 0:  // noise between frames (a loose connector, say)
        for (int i = static_cast<int>(rng() % 40); i > 0; --i) out.bytes.insert(out.bytes.begin(), static_cast<char>(rng()));
        break;
      case 1:  // a random byte of the frame changed
        out.bytes[rng() % out.bytes.size()] = static_cast<char>(rng());
        ++damaged;
        break;
      case 2:  // a piece of the frame lost
        out.bytes.erase(rng() % out.bytes.size(), 1 + rng() % 200);
        ++damaged;
        break;
      default: break;
    }
  };
  UrgDriver driver(test::emulated_opener(*device_), options());
  const Events events = run(driver, 30.0);
  EXPECT_GT(events.scans.size(), 150u) << events.fault_list();
  EXPECT_GT(damaged, 50u);
  EXPECT_TRUE(events.has_fault(UrgFault::corrupt_data));
  expect_accounted(events, 100);
  // No scan arrives with values other than those the sensor measured.
  for (const UrgScan& s : events.scans) {
    for (const std::uint32_t v : s.raw.values_mm) ASSERT_EQ(v, 1000 + s.sensor_time_ms / 100 % 1000);
  }
}

TEST(UrgDriverOptions, InvalidOptionsAreRefusedByName) {
  UrgDriverOptions o;
  o.cluster = 120;
  EXPECT_THROW(o.validate(), InputError);
  o = {};
  o.start_step = 600;
  o.end_step = 500;
  try {
    o.validate();
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("end_step"), std::string::npos);
  }
  EXPECT_THROW(UrgDriver(nullptr, {}), InputError);
}

}  // namespace
}  // namespace stridemap
