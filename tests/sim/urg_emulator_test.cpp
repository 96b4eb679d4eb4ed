// The emulator answers like the real URG-04LX units of
// ../shared/research/scip.md, byte for byte where the notes give bytes.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "stridemap/core/error.hpp"
#include "stridemap/sensors/scip_decoder.hpp"
#include "stridemap/sensors/scip_parameters.hpp"
#include "stridemap/sim/motion_source.hpp"
#include "stridemap/sim/urg_emulator.hpp"

namespace stridemap {
namespace {

class RampSource final : public UrgScanSource {
 public:
  void scan(std::uint64_t index, double, std::vector<std::uint32_t>& values) override {
    values.resize(682);
    for (std::size_t i = 0; i < values.size(); ++i) values[i] = static_cast<std::uint32_t>(100 + i + index);
    values[0] = 7;  // an error code in the first cluster
  }
};

class EmulatorTest : public ::testing::Test {
 protected:
  std::string say(UrgEmulator& e, const std::string& command, std::int64_t at_ms = 0) {
    e.receive(command, at_ms);
    return take(e);
  }
  std::string take(UrgEmulator& e) {
    std::string bytes;
    for (const EmulatorOutput& o : e.output()) bytes += o.bytes;
    e.output().clear();
    return bytes;
  }
  RampSource source_;
};

TEST_F(EmulatorTest, ClassicBootsInScip11AndSwitchesWithTheOneCharacterStatus) {
  UrgEmulator e({}, source_);
  EXPECT_FALSE(e.scip2());
  EXPECT_EQ(say(e, "QT\n"), "QT\nE\n\n");  // what the official library's probe sees from a 1.1 unit
  EXPECT_EQ(say(e, "SCIP2.0\n"), "SCIP2.0\n0\n\n");
  EXPECT_TRUE(e.scip2());
  EXPECT_FALSE(e.laser_on());  // laser off after the switch
  EXPECT_EQ(say(e, "QT\n"), "QT\n00P\n\n");
}

TEST_F(EmulatorTest, Ug01SpeaksScip2AndCallsTheSwitchUndefined) {
  UrgEmulatorOptions o;
  o.variant = UrgVariant::ug01;
  UrgEmulator e(o, source_);
  EXPECT_EQ(say(e, "SCIP2.0\n"), "SCIP2.0\n0Ee\n\n");  // the real UG01's answer
  const std::string vv = say(e, "VV\n");
  EXPECT_NE(vv.find("VEND:Hokuyo Automatic Co.,Ltd.;[\n"), std::string::npos) << vv;  // real UG01 line
  EXPECT_NE(vv.find("FIRM:3.4.03(17/Dec./2012);T\n"), std::string::npos) << vv;
  EXPECT_NE(vv.find("PROT:SCIP 2.0;N\n"), std::string::npos) << vv;
}

TEST_F(EmulatorTest, ParametersReplyDecodesToTheSensorModel) {
  UrgEmulator e({}, source_);
  say(e, "SCIP2.0\n");
  const auto events = scip::decode_all(say(e, "PP\n"));
  ASSERT_EQ(events.size(), 1u);
  ASSERT_EQ(events[0].kind, scip::EventKind::info);
  EXPECT_EQ(scip::parse_parameters(events[0].info), scip::ScipParameters{});
  const std::string pp = say(e, "PP\n");
  EXPECT_NE(pp.find("DMIN:20;4\n"), std::string::npos) << pp;  // spec example, checksum '4'
}

TEST_F(EmulatorTest, SingleScanNeedsTheLaserAndComesAtTheEndOfTheTurn) {
  UrgEmulator e({}, source_);
  say(e, "SCIP2.0\n");
  EXPECT_EQ(say(e, "GD0044072501\n", 10), "GD0044072501\n10Q\n\n");  // status 10: laser is off
  EXPECT_EQ(say(e, "BM\n", 10), "BM\n00P\n\n");
  EXPECT_EQ(say(e, "BM\n", 10), "BM\n02R\n\n");  // already on, sum 'R' as a real UG01 sends
  say(e, "GD0044072501\n", 50);
  e.advance(199);
  EXPECT_TRUE(e.output().empty());  // scan 1 starts at 100 ms and ends at 200 ms
  e.advance(200);
  ASSERT_EQ(e.output().size(), 1u);
  const EmulatorOutput out = e.output()[0];
  EXPECT_TRUE(out.is_scan);
  EXPECT_EQ(out.scan_index, 1u);
  EXPECT_EQ(out.timestamp_ms, 100u);
  const auto events = scip::decode_all(out.bytes);
  ASSERT_EQ(events.size(), 1u);
  ASSERT_EQ(events[0].kind, scip::EventKind::distance) << events[0].error.message;
  EXPECT_EQ(events[0].distance.values.size(), 682u);
  EXPECT_EQ(events[0].distance.values[0], 7u);
  EXPECT_EQ(events[0].distance.values[681], 100u + 681 + 1);
}

TEST_F(EmulatorTest, StreamCountsDownTheScansLeftAndTurnsTheLaserOffAfterTheLast) {
  UrgEmulator e({}, source_);
  say(e, "SCIP2.0\n");
  EXPECT_EQ(say(e, "MD0044072501002\n"), "MD0044072501002\n00P\n\n");
  EXPECT_TRUE(e.laser_on());  // MD turns it on itself
  e.advance(1000);
  const auto events = scip::decode_all(take(e));
  ASSERT_EQ(events.size(), 2u);
  EXPECT_EQ(events[0].reply.echo.text, "MD0044072501001");
  EXPECT_EQ(events[0].reply.status, "99");
  EXPECT_EQ(events[1].reply.echo.text, "MD0044072501000");
  EXPECT_FALSE(e.streaming());
  EXPECT_FALSE(e.laser_on());
}

TEST_F(EmulatorTest, ClusterSendsTheSmallestValidValueAndIntervalSkipsScans) {
  UrgEmulator e({}, source_);
  say(e, "SCIP2.0\n");
  say(e, "MD0044005303100\n");  // steps 44..53, clusters of 3, every other scan
  e.advance(500);
  std::vector<std::uint32_t> stamps;
  for (const EmulatorOutput& o : e.output()) {
    if (!o.is_scan) continue;
    stamps.push_back(o.timestamp_ms);
    const auto events = scip::decode_all(o.bytes);
    ASSERT_EQ(events.size(), 1u);
    const std::uint64_t k = o.scan_index;
    // Step 44 holds code 7: the cluster 44-46 sends the smallest valid value.
    EXPECT_EQ(events[0].distance.values, (std::vector<std::uint32_t>{101 + static_cast<std::uint32_t>(k),
                                                                       103 + static_cast<std::uint32_t>(k),
                                                                       106 + static_cast<std::uint32_t>(k),
                                                                       109 + static_cast<std::uint32_t>(k)}));
  }
  EXPECT_EQ(stamps, (std::vector<std::uint32_t>{0, 200, 400}));  // interval 1: scans 0, 2, 4 (sent at 100, 300, 500 ms)
}

TEST_F(EmulatorTest, MalformedOrOutOfRangeRequestsGetTheirStatus) {
  UrgEmulator e({}, source_);
  say(e, "SCIP2.0\n");
  EXPECT_EQ(say(e, "MD00x4072501000\n").substr(16, 3), "01Q");
  EXPECT_EQ(say(e, "MD0044080001000\n").substr(16, 3), "04T");  // beyond step 768
  EXPECT_EQ(say(e, "MD0500040001000\n").substr(16, 2), "05");   // end before start
  EXPECT_EQ(say(e, "XX\n"), "XX\n0Ee\n\n");
  EXPECT_EQ(say(e, "VV;12345678901234567\n").substr(21, 2), "0G");  // tag longer than 16
  EXPECT_FALSE(e.streaming());
}

TEST_F(EmulatorTest, TimestampWrapsAt24BitsAndResetRestartsTheClock) {
  UrgEmulatorOptions o;
  o.timestamp_start_ms = (1u << 24) - 150;
  UrgEmulator e(o, source_);
  say(e, "SCIP2.0\n");
  say(e, "MD0044072501000\n");
  e.advance(400);
  std::vector<std::uint32_t> stamps;
  for (const EmulatorOutput& out : e.output()) {
    if (out.is_scan) stamps.push_back(out.timestamp_ms);
  }
  e.output().clear();
  EXPECT_EQ(stamps, (std::vector<std::uint32_t>{(1u << 24) - 150, (1u << 24) - 50, 50, 150}));
  EXPECT_EQ(say(e, "RS\n", 1000), "RS\n00P\n\n");
  EXPECT_FALSE(e.streaming());
  EXPECT_EQ(e.sensor_time_ms(1000), (1u << 24) - 150);  // the timer restarted
}

TEST_F(EmulatorTest, TimeModeRefusesOtherCommandsAndReadsTheClock) {
  UrgEmulator e({}, source_);
  say(e, "SCIP2.0\n");
  EXPECT_EQ(say(e, "TM1\n"), "TM1\n04T\n\n");  // not in adjust mode
  EXPECT_EQ(say(e, "TM0\n", 5), "TM0\n00P\n\n");
  EXPECT_EQ(say(e, "QT\n", 5), "QT\n0Ee\n\n");  // the official library's cue to send TM2
  const auto events = scip::decode_all(say(e, "TM1\n", 1234));
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events[0].kind, scip::EventKind::time);
  EXPECT_EQ(events[0].time_ms, 1234u);
  EXPECT_EQ(say(e, "TM2\n"), "TM2\n00P\n\n");
}

TEST_F(EmulatorTest, StatusInfoReportsLaserAndTime) {
  UrgEmulator e({}, source_);
  say(e, "SCIP2.0\n");
  say(e, "BM\n");
  const auto events = scip::decode_all(say(e, "II\n", 0x2AA9));
  ASSERT_EQ(events.size(), 1u);
  ASSERT_EQ(events[0].kind, scip::EventKind::info) << events[0].error.message;
  const scip::StatusInfo info = scip::parse_status_info(events[0].info);
  EXPECT_TRUE(info.laser_on);
  EXPECT_EQ(info.time_ms, 0x2AA9u);
}

TEST_F(EmulatorTest, PowerCycleGoesBackToScip11WithTheLaserOff) {
  UrgEmulator e({}, source_);
  say(e, "SCIP2.0\n");
  say(e, "MD0044072501000\n");
  e.power_cycle(5000);
  EXPECT_FALSE(e.scip2());
  EXPECT_FALSE(e.streaming());
  EXPECT_EQ(e.sensor_time_ms(5000), 0u);
}

TEST_F(EmulatorTest, OptionsThatNoUnitHasAreRefused) {
  UrgEmulatorOptions o;
  o.parameters.motor_speed_rpm = 700;  // 85.7 ms per turn
  EXPECT_THROW(UrgEmulator(o, source_), InputError);
  o = {};
  o.timestamp_start_ms = 1u << 24;
  EXPECT_THROW(UrgEmulator(o, source_), InputError);
}

TEST(MotionSource, CartRailMovesOneStepPerScanAndStopsAtTheEnd) {
  const CartRailMotion rail({0.0, 0.1, 0.2, 0.01, 0.0}, 0.1);
  EXPECT_EQ(rail.positions(), 11u);
  EXPECT_DOUBLE_EQ(rail.pose_at(0.0).x_m, 0.0);
  EXPECT_DOUBLE_EQ(rail.pose_at(0.3).x_m, 0.03);
  EXPECT_DOUBLE_EQ(rail.pose_at(0.35).x_m, 0.03);
  EXPECT_DOUBLE_EQ(rail.pose_at(50.0).x_m, 0.1);
  EXPECT_DOUBLE_EQ(rail.pose_at(0.3).y_m, 0.2);
  EXPECT_THROW(CartRailMotion({0.0, 0.1, 0.0, 0.01, 0.0}, 0.0), InputError);
  TrunkPose bad;
  bad.x_m = std::nan("");
  EXPECT_THROW(StaticMotion{bad}, InputError);
}

}  // namespace
}  // namespace stridemap

namespace stridemap {
namespace {

// Whatever commands a host sends (valid or with bad parameters), in
// whatever pieces, the emulator answers with frames that decode cleanly: a
// sensor never sends malformed SCIP. (Replies to lines that are no command
// at all are echoed as they came, and a decoder calls those unknown or
// garbage by design: they are fed in the next test, for robustness only.)
TEST(UrgEmulatorRandomInput, EveryReplyToRandomCommandsDecodesCleanly) {
  class Flat final : public UrgScanSource {
   public:
    void scan(std::uint64_t, double, std::vector<std::uint32_t>& v) override { v.assign(682, 1500); }
  } source;
  std::mt19937_64 rng(11);
  const std::vector<std::string> commands = {"MD0044072501000", "GD0044072501", "BM", "QT", "RS", "VV", "PP", "II",
                                             "TM0", "TM1", "TM2", "SCIP2.0", "MS0000076899103", "MD0044072501000;t1",
                                             "GD00x4072501", "CR05", "SS115200", "HS1", "DB01"};
  for (const UrgVariant variant : {UrgVariant::classic, UrgVariant::ug01}) {
    UrgEmulatorOptions o;
    o.variant = variant;
    o.timestamp_start_ms = (1u << 24) - 5000;
    UrgEmulator e(o, source);
    scip::Decoder decoder;
    scip::Event event;
    std::int64_t now = 0;
    std::size_t replies = 0;
    std::string host;
    for (int k = 0; k < 3000; ++k) {
      host += commands[rng() % commands.size()];
      host += rng() % 5 == 0 ? "\r\n" : "\n";
      // Sent in random pieces, at random times.
      while (host.size() > 40 || (!host.empty() && rng() % 2 == 0)) {
        const std::size_t n = 1 + rng() % host.size();
        now += static_cast<std::int64_t>(rng() % 30);
        e.advance(now);
        e.receive(host.substr(0, n), now);
        host.erase(0, n);
      }
      for (const EmulatorOutput& out : e.output()) decoder.feed(out.bytes);
      e.output().clear();
      while (decoder.next(event)) {
        ASSERT_NE(event.kind, scip::EventKind::error) << event.error.message;
        ++replies;
      }
    }
    EXPECT_GT(replies, 1000u);
  }
}

TEST(UrgEmulatorRandomInput, RandomBytesNeitherCrashNorBreakTheOutput) {
  class Flat final : public UrgScanSource {
   public:
    void scan(std::uint64_t, double, std::vector<std::uint32_t>& v) override { v.assign(682, 1500); }
  } source;
  std::mt19937_64 rng(12);
  UrgEmulator e({}, source);
  e.receive("SCIP2.0\nMD0044072501000\n", 0);
  for (int k = 0; k < 20000; ++k) {
    std::string bytes;
    for (int i = static_cast<int>(rng() % 8); i > 0; --i) bytes += static_cast<char>(rng() % 256);
    e.advance(k);
    e.receive(bytes, k);
  }
  for (const EmulatorOutput& out : e.output()) {
    for (const char c : out.bytes) ASSERT_TRUE(c == '\n' || (c >= 0x20 && c <= 0x7E)) << "unprintable byte sent";
  }
}

}  // namespace
}  // namespace stridemap
