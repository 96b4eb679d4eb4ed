// The scan log kept during live mapping (live/scan_recorder.hpp): what it
// records and in which order, appending to an earlier log, and a failed
// write that ends the recording but not the run.
#include <gtest/gtest.h>

#include <sys/resource.h>

#include <csignal>
#include <string>

#include "live/test_folder.hpp"
#include "stridemap/core/error.hpp"
#include "stridemap/live/scan_recorder.hpp"
#include "stridemap/recordings/scan_log.hpp"

namespace stridemap {
namespace {

class RecordedSensor final : public LiveScanSource {
 public:
  scip::ScipParameters current;
  bool next(UrgDriverEvent&, double) override { return false; }
  scip::ScipParameters parameters() const override { return current; }
  scip::VersionInfo version() const override { return {"Hokuyo", "URG-04LX", "3.3.00", "SCIP 2.0", "H1"}; }
  UrgDriverStats stats() const override { return {}; }
  void stop() override {}
};

UrgScan recorded_scan(std::uint64_t k) {
  UrgScan s;
  s.sequence = k;
  s.host_time_s = 70.0 + 0.1 * static_cast<double>(k);
  s.host_receive_time_s = s.host_time_s + 0.01;
  s.sensor_time_ms = 100 * k;
  s.raw.first_step = 44;
  s.raw.cluster = 1;
  s.raw.values_mm.assign(682, 600);
  return s;
}

LiveEvent fault_event(const UrgDriverEvent& driver_event) {
  LiveEvent e;
  e.kind = LiveEvent::Kind::fault;
  e.message = driver_event.message;
  e.driver_event = &driver_event;
  return e;
}

TEST(ScanRecorder, WithoutALogRecordsNothingAndNeverFails) {
  ScanRecorder recorder;
  const RecordedSensor sensor;
  EXPECT_FALSE(recorder.recording());
  EXPECT_TRUE(recorder.scan(recorded_scan(0)));
  EXPECT_TRUE(recorder.event(LiveEvent{}, sensor));
  EXPECT_TRUE(recorder.flush());
  EXPECT_TRUE(recorder.error().empty());
}

TEST(ScanRecorder, RecordsTheSensorScansAndFaultsInOrder) {
  test::TestFolder dir;
  const RecordedSensor sensor;
  {
    ScanRecorder recorder(dir / "log.txt", "/dev/ttyACM0", false, sensor);
    EXPECT_TRUE(recorder.recording());
    for (std::uint64_t k = 0; k < 3; ++k) EXPECT_TRUE(recorder.scan(recorded_scan(k)));
    UrgDriverEvent lost;
    lost.fault = UrgFault::scans_lost;
    lost.count = 2;
    lost.message = "2 scans missing";
    EXPECT_TRUE(recorder.event(fault_event(lost), sensor));
    LiveEvent status;  // not the log's
    EXPECT_TRUE(recorder.event(status, sensor));
    LiveEvent connected;
    connected.kind = LiveEvent::Kind::connected;
    EXPECT_TRUE(recorder.event(connected, sensor));
    EXPECT_TRUE(recorder.scan(recorded_scan(3)));
    EXPECT_TRUE(recorder.flush());
    EXPECT_TRUE(recorder.error().empty());
  }
  const io::ScanLog log = io::read_scan_log(dir / "log.txt");
  EXPECT_EQ(log.device, "/dev/ttyACM0");
  ASSERT_EQ(log.scans.size(), 4u);
  EXPECT_EQ(log.scans[3].sequence, 3u);
  EXPECT_EQ(log.scans[1].raw.values_mm, recorded_scan(1).raw.values_mm);
  ASSERT_EQ(log.faults.size(), 1u);
  EXPECT_EQ(log.faults[0].count, 2u);
  EXPECT_EQ(log.faults[0].message, "2 scans missing");
  EXPECT_TRUE(log.stop.empty()) << log.stop;
  const std::string text = dir.read("log.txt");
  const std::size_t first_sensor = text.find("\nsensor ");
  ASSERT_NE(first_sensor, std::string::npos);
  EXPECT_NE(text.find("\nsensor ", first_sensor + 1), std::string::npos) << "the reconnection's sensor block";
}

TEST(ScanRecorder, AppendsToAnEarlierLog) {
  test::TestFolder dir;
  const RecordedSensor sensor;
  {
    ScanRecorder first(dir / "log.txt", "/dev/ttyACM0", false, sensor);
    first.scan(recorded_scan(0));
  }
  {
    ScanRecorder second(dir / "log.txt", "/dev/ttyACM0", true, sensor);
    second.scan(recorded_scan(1));
  }
  EXPECT_EQ(io::read_scan_log(dir / "log.txt").scans.size(), 2u);
}

TEST(ScanRecorder, AFolderThatDoesNotExistIsRefusedAtTheStart) {
  test::TestFolder dir;
  const RecordedSensor sensor;
  EXPECT_THROW(ScanRecorder(dir / "no/such/folder/log.txt", "x", false, sensor), InputError);
}

TEST(ScanRecorder, AFailedWriteEndsTheRecordingAndIsKept) {
  test::TestFolder dir;
  const RecordedSensor sensor;
  ScanRecorder recorder(dir / "log.txt", "/dev/ttyACM0", false, sensor);
  rlimit old_limit{};
  ASSERT_EQ(::getrlimit(RLIMIT_FSIZE, &old_limit), 0);
  const auto old_handler = std::signal(SIGXFSZ, SIG_IGN);
  rlimit small = old_limit;
  small.rlim_cur = 16384;  // room for a few scans of ~2.5 kB
  ASSERT_EQ(::setrlimit(RLIMIT_FSIZE, &small), 0);
  std::size_t written = 0;
  bool failed = false;
  for (std::uint64_t k = 0; k < 20 && !failed; ++k) {
    failed = !recorder.scan(recorded_scan(k));
    written += failed ? 0 : 1;
  }
  const bool after = recorder.scan(recorded_scan(99));
  ::setrlimit(RLIMIT_FSIZE, &old_limit);
  std::signal(SIGXFSZ, old_handler);

  ASSERT_TRUE(failed);
  EXPECT_GT(written, 0u);
  EXPECT_TRUE(after) << "nothing more is tried, so nothing more fails";
  EXPECT_FALSE(recorder.recording());
  EXPECT_NE(recorder.error().find("log.txt"), std::string::npos) << recorder.error();
  EXPECT_TRUE(recorder.flush());
}

}  // namespace
}  // namespace stridemap
