#include "stridemap/recordings/log_import.hpp"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <iomanip>
#include <numbers>
#include <sstream>

#include <gtest/gtest.h>

#include "live/test_folder.hpp"
#include "stridemap/core/error.hpp"
#include "stridemap/recordings/pose_stream.hpp"
#include "stridemap/recordings/scan_log.hpp"
#include "stridemap/sensors/scip_parameters.hpp"
#include "stridemap/sensors/urg04lx.hpp"
#include "test_paths.hpp"

namespace stridemap {
namespace {

using test::TestFolder;
constexpr double kPi = std::numbers::pi;

const std::filesystem::path kExp1 =
    std::filesystem::path(STRIDEMAP_SHARED_DATA_DIR) / "urg04lx_breezyslam" / "exp1.dat";

std::string read_text(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// A BreezySLAM line: time, 23 robot fields (ticks at 2 and 3), `values` ranges.
std::string breezyslam_line(std::uint64_t time_us, long left, long right, std::size_t values, std::uint32_t range) {
  std::ostringstream line;
  line << time_us << " 0 " << left << " " << right;
  for (int k = 4; k < 24; ++k) line << " 0";
  for (std::size_t k = 0; k < values; ++k) line << " " << range;
  line << "\n";
  return line.str();
}

// A FLASER line of 3 readings at `time`.
std::string flaser_line(const std::string& time) {
  return "FLASER 3 1.0 1.5 2.0 0 0 0 0 0 0 " + time + " host " + time + "\n";
}

// A TUM line at `time`, x = time.
std::string tum_line(double time) {
  std::ostringstream line;
  line.precision(17);
  line << time << " " << time << " 0 0 0 0 0 1\n";
  return line.str();
}

// A CSV ranges line of 3 ranges at `time`.
std::string csv_line(double time) {
  std::ostringstream line;
  line.precision(17);
  line << time << ",1,1,1\n";
  return line.str();
}

io::CsvRangesImportOptions three_beams() {
  io::CsvRangesImportOptions options;
  options.angle_min_rad = -kPi / 4;
  options.angle_step_rad = kPi / 4;
  return options;
}

bool starts_with(const std::string& text, const std::string& start) { return text.rfind(start, 0) == 0; }

constexpr const char* kBom = "\xEF\xBB\xBF";

// Angles of the beams as the scan log's sensor model puts them.
std::vector<double> beam_angles(const io::ImportedData& data) {
  const UrgParameters sensor = scip::to_urg_parameters(data.sensor);
  std::vector<double> angles;
  const UrgRawScan& raw = data.scans.front().raw;
  for (std::size_t k = 0; k < raw.values_mm.size(); ++k) {
    angles.push_back(sensor.step_angle_rad(raw.first_step + static_cast<double>(k) * raw.cluster));
  }
  return angles;
}

TEST(BreezySlamImport, DeadReckonsTheWheelOdometry) {
  io::BreezySlamImportOptions options;
  options.values_per_scan = 5;
  // Straight: both wheels one revolution (4000 ticks): 2 pi r forward.
  // Then the right wheel alone 1000 ticks: a turn left on the spot's edge.
  const std::string text = breezyslam_line(1000000, 0, 0, 5, 1000) + breezyslam_line(1100000, 4000, 4000, 5, 1000) +
                           breezyslam_line(1200000, 4000, 5000, 5, 1000);
  const io::ImportedData data = io::import_breezyslam(text, "rover.dat", options);
  ASSERT_EQ(data.scans.size(), 3u);
  ASSERT_EQ(data.poses.size(), 3u);
  EXPECT_EQ(data.report.skipped, 0u);
  EXPECT_DOUBLE_EQ(data.poses[1].time_s, 1.1);
  EXPECT_NEAR(data.poses[1].pose.x_m, 2 * kPi * 0.077, 1e-12);
  EXPECT_NEAR(data.poses[1].pose.y_m, 0.0, 1e-12);
  const double arc = 2 * kPi * 0.077 / 4;  // the right wheel's travel
  EXPECT_NEAR(data.poses[2].pose.yaw_rad, arc / (2 * 0.165), 1e-12);
  EXPECT_NEAR(data.poses[2].pose.x_m - data.poses[1].pose.x_m, 0.5 * arc * std::cos(arc / (4 * 0.165)), 1e-12);
  EXPECT_EQ(data.scans[2].raw.values_mm, std::vector<std::uint32_t>(5, 1000));
  EXPECT_EQ(data.scans[2].raw.first_step, 44);
  EXPECT_EQ(data.scans[2].sensor_time_ms, 200u);
}

TEST(BreezySlamImport, MalformedLinesAreSkippedAndReportedWithTheirLine) {
  io::BreezySlamImportOptions options;
  options.values_per_scan = 3;
  std::string text = breezyslam_line(1000, 0, 0, 3, 500);
  text += "1100 0 0 0\n";                                // too few fields
  text += breezyslam_line(900, 0, 0, 3, 500);            // time goes back
  std::string bad_range = breezyslam_line(1200, 0, 0, 3, 500);
  bad_range.replace(bad_range.rfind("500"), 3, "5x0");
  text += bad_range;
  text += "\n# a comment\n";
  text += breezyslam_line(1300, 10, 10, 3, 500);
  const io::ImportedData data = io::import_breezyslam(text, "rover.dat", options);
  EXPECT_EQ(data.scans.size(), 2u);
  EXPECT_EQ(data.report.skipped, 3u);
  EXPECT_EQ(data.report.ignored, 2u);
  EXPECT_EQ(data.report.lines, 7u);
  ASSERT_EQ(data.report.problems.size(), 3u);
  EXPECT_EQ(data.report.problems[0].rfind("rover.dat:2: 4 fields, expected 27", 0), 0u) << data.report.problems[0];
  EXPECT_EQ(data.report.problems[1].rfind("rover.dat:3: time 900 us is out of order", 0), 0u) << data.report.problems[1];
  EXPECT_EQ(data.report.problems[2].rfind("rover.dat:4: range 3 ('5x0')", 0), 0u) << data.report.problems[2];
}

TEST(BreezySlamImport, BadOptionsAreRefused) {
  io::BreezySlamImportOptions options;
  options.wheel_radius_m = 0.0;
  EXPECT_THROW(io::import_breezyslam("", "x.dat", options), InputError);
  options = {};
  options.values_per_scan = 2000;  // beyond the URG's 1024 steps
  EXPECT_THROW(io::import_breezyslam("", "x.dat", options), InputError);
}

TEST(BreezySlamImport, RealRecordingImportsEveryScan) {
  if (!std::filesystem::exists(kExp1)) GTEST_SKIP() << "no real recording at " << kExp1 << " (../shared/data absent)";
  const io::ImportedData data = io::import_breezyslam(read_text(kExp1), kExp1.string());
  EXPECT_EQ(data.scans.size(), 756u);
  EXPECT_EQ(data.poses.size(), 756u);
  EXPECT_EQ(data.report.skipped, 0u);
  EXPECT_EQ(data.sensor.last_step, 726);  // 683 values from step 44
  // The rover drives a few metres through the corridors, not kilometres.
  double path = 0.0;
  for (std::size_t k = 1; k < data.poses.size(); ++k) {
    path += std::hypot(data.poses[k].pose.x_m - data.poses[k - 1].pose.x_m,
                       data.poses[k].pose.y_m - data.poses[k - 1].pose.y_m);
  }
  EXPECT_GT(path, 1.0);
  EXPECT_LT(path, 100.0);
  const double duration = data.poses.back().time_s - data.poses.front().time_s;
  EXPECT_NEAR(duration / 755.0, 0.1, 0.05);  // about 10 Hz
}

TEST(CarmenImport, ReadsFlaserAndRobotLaserLines) {
  std::ostringstream log;
  log << "# CARMEN Logfile\nPARAM robot_use_laser on nohost 0\n";
  log << "ODOM 0 0 0 0 0 0 0.5 host 0.5\n";
  // FLASER: 181 readings (1 deg), pose, odometry, timestamps.
  log << "FLASER 181";
  for (int k = 0; k < 181; ++k) log << " " << (k == 90 ? 2.5 : 81.9);
  log << " 1.0 2.0 0.5 1.0 2.0 0.5 10.0 host 10.01\n";
  // ROBOTLASER1: type, start, fov, resolution, max range, accuracy, remission mode,
  // 181 readings, 0 remissions, laser pose, robot pose, tv rv fsd ssd turn, timestamps.
  log << std::fixed << std::setprecision(6);  // as CARMEN prints angles: 0.017453 for 1 deg
  log << "ROBOTLASER1 0 " << -kPi / 2 << " " << kPi << " " << kPi / 180 << " 81.9 0.01 0 181";
  for (int k = 0; k < 181; ++k) log << " " << (k == 0 ? 0.0 : 3.0);
  log << " 0 1.1 2.0 0.5 1.2 2.1 0.6 0 0 0 0 0 10.1 host 10.11\n";
  log << "FLASER 3 1 2\n";  // cut short
  const io::ImportedData data = io::import_carmen(log.str(), "run.clf");
  ASSERT_EQ(data.scans.size(), 2u);
  EXPECT_EQ(data.report.ignored, 3u);
  EXPECT_EQ(data.report.skipped, 1u);
  ASSERT_EQ(data.report.problems.size(), 1u);
  EXPECT_EQ(data.report.problems[0].rfind("run.clf:6: FLASER with 3 readings has 4 fields", 0), 0u)
      << data.report.problems[0];
  EXPECT_EQ(data.sensor.steps_per_turn, 360);
  EXPECT_EQ(data.sensor.front_step, 90);
  EXPECT_EQ(data.sensor.max_distance_mm, 81900);
  const auto angles = beam_angles(data);
  EXPECT_NEAR(angles.front(), -kPi / 2, 1e-12);
  EXPECT_NEAR(angles[90], 0.0, 1e-12);
  EXPECT_NEAR(angles.back(), kPi / 2, 1e-12);
  EXPECT_EQ(data.scans[0].raw.values_mm[90], 2500u);
  EXPECT_GT(data.scans[0].raw.values_mm[0], 81900u);  // the maximum range means no return
  EXPECT_EQ(data.scans[1].raw.values_mm[0], 0u);       // zero: no return either
  ASSERT_EQ(data.poses.size(), 2u);
  EXPECT_DOUBLE_EQ(data.poses[1].pose.x_m, 1.2);  // the robot's pose, not the laser's
  EXPECT_DOUBLE_EQ(data.poses[1].pose.yaw_rad, 0.6);
  EXPECT_DOUBLE_EQ(data.poses[1].time_s, 10.1);
  // Through the sensor model the front beam is 2.5 m straight ahead.
  UrgModel model(scip::to_urg_parameters(data.sensor));
  PlanarScan scan;
  model.to_planar_scan(data.scans[0].raw, scan);
  EXPECT_NEAR(scan.range_m[90], 2.5, 1e-9);
  EXPECT_TRUE(std::isnan(scan.range_m[0]));
}

TEST(CarmenImport, FlaserWith180ReadingsUsesFinerSteps) {
  std::ostringstream log;
  log << "FLASER 180";
  for (int k = 0; k < 180; ++k) log << " 1.5";
  log << " 0 0 0 0 0 0 1.0 host 1.0\n";
  const io::ImportedData data = io::import_carmen(log.str(), "old.log");
  ASSERT_EQ(data.scans.size(), 1u) << (data.report.problems.empty() ? "" : data.report.problems[0]);
  const auto angles = beam_angles(data);
  EXPECT_NEAR(angles.front(), -kPi / 2, 1e-12);
  EXPECT_NEAR(angles.back(), kPi / 2, 1e-12);
  EXPECT_NEAR(angles[1] - angles[0], kPi / 179, 1e-12);
}

TEST(CsvRangesImport, ReadsRangesWithTheirAnglesAndReportsBadLines) {
  const std::string text =
      "time_s,r0,r1,r2\n"
      "0.0, 1000, 2000, 3000\n"
      "0.1\t1000\t0\t9000\n"
      "0.2,1000,abc,3000\n"
      "0.3,1000,2000\n"
      "0.05,1,1,1\n"
      "0.4,nan,1500,1500\n";
  io::CsvRangesImportOptions options;
  options.angle_min_rad = -kPi / 4;
  options.angle_step_rad = kPi / 4;
  options.range_scale_m = 0.001;
  options.max_range_m = 5.0;
  const io::ImportedData data = io::import_csv_ranges(text, "ranges.csv", options);
  ASSERT_EQ(data.scans.size(), 3u);
  EXPECT_EQ(data.report.ignored, 1u);
  EXPECT_EQ(data.report.skipped, 3u);
  ASSERT_EQ(data.report.problems.size(), 3u);
  EXPECT_EQ(data.report.problems[0].rfind("ranges.csv:4: range 2 ('abc')", 0), 0u) << data.report.problems[0];
  EXPECT_EQ(data.report.problems[1].rfind("ranges.csv:5: 2 ranges, the first scan had 3", 0), 0u);
  EXPECT_EQ(data.report.problems[2].rfind("ranges.csv:6: time 0.05 is out of order", 0), 0u);
  EXPECT_EQ(data.scans[0].raw.values_mm, (std::vector<std::uint32_t>{1000, 2000, 3000}));
  EXPECT_EQ(data.scans[1].raw.values_mm[1], 0u);
  EXPECT_GT(data.scans[1].raw.values_mm[2], 5000u);
  EXPECT_EQ(data.scans[2].raw.values_mm[0], 0u);
  const auto angles = beam_angles(data);
  EXPECT_NEAR(angles[0], -kPi / 4, 1e-12);
  EXPECT_NEAR(angles[2], kPi / 4, 1e-12);
  EXPECT_TRUE(data.poses.empty());
}

TEST(CsvRangesImport, AnglesThatAreNotWholeStepsAreAClearError) {
  io::CsvRangesImportOptions options;
  options.angle_min_rad = -0.5;
  options.angle_step_rad = 0.0123;
  try {
    io::import_csv_ranges("0,1,1,1\n", "odd.csv", options);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("odd.csv"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("whole steps"), std::string::npos) << e.what();
  }
  options.angle_min_rad = 0.1;  // every beam to the left: no forward step
  options.angle_step_rad = kPi / 180;
  EXPECT_THROW(io::import_csv_ranges("0,1,1,1\n", "left.csv", options), InputError);
}

TEST(TumImport, QuaternionsBecomeYawPitchRoll) {
  const double yaw = 0.7, pitch = 0.1, roll = -0.2;
  // q = qz(yaw) qy(pitch) qx(roll), written out.
  const double cy = std::cos(yaw / 2), sy = std::sin(yaw / 2), cp = std::cos(pitch / 2), sp = std::sin(pitch / 2);
  const double cr = std::cos(roll / 2), sr = std::sin(roll / 2);
  const double qw = cy * cp * cr + sy * sp * sr, qx = cy * cp * sr - sy * sp * cr;
  const double qy = cy * sp * cr + sy * cp * sr, qz = sy * cp * cr - cy * sp * sr;
  std::ostringstream text;
  text.precision(17);
  text << "# timestamp tx ty tz qx qy qz qw\n";
  text << "1.0 0.5 -0.25 1.0 0 0 0 1\n";
  text << "1.1 0.6 -0.25 1.05 " << qx << " " << qy << " " << qz << " " << qw << "\n";
  text << "1.2 0.6 -0.25 1.05 0 0 0 2\n";    // not a unit quaternion
  text << "1.05 0.6 -0.25 1.05 0 0 0 1\n";   // time goes back
  text << "1.3 0.6 -0.25 1.05 0 0 0\n";      // a field missing
  const io::ImportedData data = io::import_tum(text.str(), "traj.txt");
  ASSERT_EQ(data.poses.size(), 2u);
  EXPECT_TRUE(data.scans.empty());
  EXPECT_EQ(data.report.skipped, 3u);
  EXPECT_EQ(data.report.problems[0].rfind("traj.txt:4: the quaternion's length", 0), 0u) << data.report.problems[0];
  EXPECT_EQ(data.report.problems[2].rfind("traj.txt:6: 7 fields", 0), 0u) << data.report.problems[2];
  const TrunkPose& p = data.poses[1].pose;
  EXPECT_NEAR(p.yaw_rad, yaw, 1e-12);
  EXPECT_NEAR(p.pitch_rad, pitch, 1e-12);
  EXPECT_NEAR(p.roll_rad, roll, 1e-12);
  EXPECT_NEAR(p.reference_elevation_m, 0.05, 1e-12);  // tz relative to the first pose
  EXPECT_DOUBLE_EQ(p.x_m, 0.6);
  io::TumImportOptions ignore;
  ignore.height = io::TumHeight::ignore;
  EXPECT_EQ(io::import_tum(text.str(), "traj.txt", ignore).poses[1].pose.reference_elevation_m, 0.0);
}

// One far-future time ahead of good ones must not make every later record
// "out of order": the longest increasing run of times is what is kept.
TEST(ImportTimes, CarmenFarFutureTimeSkipsOnlyThatScan) {
  std::string log = flaser_line("1.0") + flaser_line("1e308");
  for (int k = 1; k <= 25; ++k) log += flaser_line(std::to_string(1.0 + 0.1 * k));
  const io::ImportedData data = io::import_carmen(log, "run.clf");
  EXPECT_EQ(data.scans.size(), 26u);
  EXPECT_EQ(data.poses.size(), 26u);
  EXPECT_EQ(data.report.skipped, 1u);
  EXPECT_EQ(data.report.out_of_order, 1u);
  ASSERT_EQ(data.report.problems.size(), 1u);
  EXPECT_TRUE(starts_with(data.report.problems[0], "run.clf:2: time 1e+308 is out of order"))
      << data.report.problems[0];
  EXPECT_DOUBLE_EQ(data.scans.back().host_time_s, 3.5);
  EXPECT_EQ(data.scans.back().sequence, 25u);
  EXPECT_EQ(data.scans.back().sensor_time_ms, 2500u);
}

TEST(ImportTimes, NonFiniteTimesAreSkippedAndNamed) {
  const std::string log = flaser_line("1.0") + flaser_line("inf") + flaser_line("nan") + flaser_line("1.2");
  const io::ImportedData data = io::import_carmen(log, "run.clf");
  EXPECT_EQ(data.scans.size(), 2u);
  EXPECT_EQ(data.report.skipped, 2u);
  ASSERT_EQ(data.report.problems.size(), 2u);
  EXPECT_EQ(data.report.problems[0], "run.clf:2: FLASER: the timestamp 'inf' is not a finite number");
  EXPECT_EQ(data.report.problems[1], "run.clf:3: FLASER: the timestamp 'nan' is not a finite number");
  const io::ImportedData tum = io::import_tum(tum_line(1.0) + "inf 0 0 0 0 0 0 1\n" + tum_line(2.0), "t.txt");
  EXPECT_EQ(tum.poses.size(), 2u);
  ASSERT_EQ(tum.report.problems.size(), 1u);
  EXPECT_TRUE(starts_with(tum.report.problems[0], "t.txt:2: field 1 ('inf') is not a finite number"));
  const io::ImportedData csv = io::import_csv_ranges(csv_line(0.0) + "nan,1,1,1\n" + csv_line(0.1), "c.csv",
                                                     three_beams());
  EXPECT_EQ(csv.scans.size(), 2u);
  ASSERT_EQ(csv.report.problems.size(), 1u);
  EXPECT_TRUE(starts_with(csv.report.problems[0], "c.csv:2: time 'nan' is not a number"));
}

TEST(ImportTimes, TumSwappedPairKeepsAllButOne) {
  std::string text;
  for (int k = 1; k <= 50; ++k) text += tum_line(k == 20 ? 21.0 : k == 21 ? 20.0 : k);
  const io::ImportedData data = io::import_tum(text, "traj.txt");
  EXPECT_EQ(data.poses.size(), 49u);
  EXPECT_EQ(data.report.skipped, 1u);
  EXPECT_EQ(data.report.out_of_order, 1u);
  ASSERT_EQ(data.report.problems.size(), 1u);
  // Of the pair, the earlier line is kept.
  EXPECT_TRUE(starts_with(data.report.problems[0], "traj.txt:21: time 20 is out of order")) << data.report.problems[0];
  EXPECT_DOUBLE_EQ(data.poses[19].time_s, 21.0);
}

// The swap the old rule handled worst: line 13 holds the last pose's time.
TEST(ImportTimes, TumDistantSwapSkipsOnlyTheSwappedPair) {
  std::string text;
  for (int k = 1; k <= 50; ++k) text += tum_line(k == 13 ? 50.0 : k == 50 ? 13.0 : k);
  const io::ImportedData data = io::import_tum(text, "traj.txt");
  EXPECT_EQ(data.poses.size(), 48u);
  EXPECT_EQ(data.report.out_of_order, 2u);
  ASSERT_EQ(data.report.problems.size(), 2u);
  EXPECT_TRUE(starts_with(data.report.problems[0], "traj.txt:13: time 50 is out of order: the records kept around "
                                                   "it are line 12 (time 12) and line 14 (time 14)"))
      << data.report.problems[0];
  EXPECT_TRUE(starts_with(data.report.problems[1], "traj.txt:50: time 13 is out of order")) << data.report.problems[1];
}

TEST(ImportTimes, BreezySlamBadTimeSkipsOnlyThatScan) {
  io::BreezySlamImportOptions options;
  options.values_per_scan = 3;
  std::string text;
  for (int k = 0; k < 60; ++k) {
    text += breezyslam_line(k == 30 ? 999999999999999u : 1000000u + 100000u * k, 10 * k, 10 * k, 3, 500);
  }
  const io::ImportedData data = io::import_breezyslam(text, "rover.dat", options);
  EXPECT_EQ(data.scans.size(), 59u);
  EXPECT_EQ(data.poses.size(), 59u);
  EXPECT_EQ(data.report.out_of_order, 1u);
  ASSERT_EQ(data.report.problems.size(), 1u);
  EXPECT_TRUE(starts_with(data.report.problems[0], "rover.dat:31: time 999999999999999 us is out of order"))
      << data.report.problems[0];
  // Dead reckoning runs over the kept scans: the skipped one's ticks are not used.
  EXPECT_NEAR(data.poses.back().pose.x_m, 590 * 2 * kPi * 0.077 / 4000, 1e-12);
}

TEST(ImportTimes, AllTimesDecreasingKeepsTheFirstRecord) {
  std::string text;
  for (int k = 5; k >= 1; --k) text += tum_line(k);
  const io::ImportedData data = io::import_tum(text, "back.txt");
  ASSERT_EQ(data.poses.size(), 1u);
  EXPECT_DOUBLE_EQ(data.poses[0].time_s, 5.0);
  EXPECT_EQ(data.report.skipped, 4u);
  EXPECT_EQ(data.report.out_of_order, 4u);
  ASSERT_EQ(data.report.problems.size(), 4u);
  EXPECT_TRUE(starts_with(data.report.problems[0], "back.txt:2: time 4 is out of order")) << data.report.problems[0];
  EXPECT_TRUE(starts_with(data.report.problems[3], "back.txt:5: time 1 is out of order")) << data.report.problems[3];
}

TEST(ImportTimes, ADuplicateTimeKeepsTheFirstOfThem) {
  const std::string text = csv_line(0.0) + csv_line(0.1) + csv_line(0.1) + csv_line(0.2);
  const io::ImportedData data = io::import_csv_ranges(text, "dup.csv", three_beams());
  ASSERT_EQ(data.scans.size(), 3u);
  EXPECT_EQ(data.report.out_of_order, 1u);
  ASSERT_EQ(data.report.problems.size(), 1u);
  EXPECT_TRUE(starts_with(data.report.problems[0], "dup.csv:3: time 0.1 repeats line 2's")) << data.report.problems[0];
  EXPECT_DOUBLE_EQ(data.scans[2].host_time_s, 0.2);
}

TEST(ImportTimes, OutOfOrderAndMalformedLinesAreReportedInLineOrder) {
  const std::string text = csv_line(0.0) + csv_line(5.0) + "0.2,1,x,1\n" + csv_line(0.3);
  const io::ImportedData data = io::import_csv_ranges(text, "mixed.csv", three_beams());
  EXPECT_EQ(data.scans.size(), 2u);
  EXPECT_EQ(data.report.skipped, 2u);
  EXPECT_EQ(data.report.out_of_order, 1u);
  ASSERT_EQ(data.report.problems.size(), 2u);
  // 0.0 and 5.0 against 0.0 and 0.3: a tie, the earlier line is kept.
  EXPECT_TRUE(starts_with(data.report.problems[0], "mixed.csv:3: range 2")) << data.report.problems[0];
  EXPECT_TRUE(starts_with(data.report.problems[1], "mixed.csv:4: time 0.3 is out of order")) << data.report.problems[1];
}

TEST(ImportBom, CarmenFirstLineAfterAByteOrderMarkIsRead) {
  const io::ImportedData data = io::import_carmen(kBom + flaser_line("1.0") + flaser_line("1.1"), "bom.clf");
  EXPECT_EQ(data.scans.size(), 2u);
  EXPECT_EQ(data.report.ignored, 0u);
  EXPECT_EQ(data.report.skipped, 0u);
}

TEST(ImportBom, TumFirstLineAfterAByteOrderMarkIsRead) {
  const io::ImportedData data = io::import_tum(kBom + tum_line(1.0) + tum_line(2.0), "bom.txt");
  EXPECT_EQ(data.poses.size(), 2u);
  EXPECT_EQ(data.report.skipped, 0u) << (data.report.problems.empty() ? "" : data.report.problems[0]);
}

TEST(ImportBom, BreezySlamFirstLineAfterAByteOrderMarkIsRead) {
  io::BreezySlamImportOptions options;
  options.values_per_scan = 3;
  const io::ImportedData data = io::import_breezyslam(
      kBom + breezyslam_line(1000, 0, 0, 3, 500) + breezyslam_line(2000, 0, 0, 3, 500), "bom.dat", options);
  EXPECT_EQ(data.scans.size(), 2u);
  EXPECT_EQ(data.report.skipped, 0u) << (data.report.problems.empty() ? "" : data.report.problems[0]);
}

TEST(ImportBom, CsvHeaderAfterAByteOrderMarkIsRecognised) {
  const io::ImportedData data =
      io::import_csv_ranges(kBom + csv_line(0.0) + csv_line(0.1), "bom.csv", three_beams());
  EXPECT_EQ(data.scans.size(), 2u);
  EXPECT_EQ(data.report.ignored, 0u);
  const io::ImportedData header =
      io::import_csv_ranges(std::string(kBom) + "time,a,b,c\n" + csv_line(0.0), "bomh.csv", three_beams());
  EXPECT_EQ(header.scans.size(), 1u);
  EXPECT_EQ(header.report.ignored, 1u);
  EXPECT_EQ(header.report.skipped, 0u);
}

TEST(ImportChecks, BinaryTextIsRefusedBeforeParsing) {
  const std::string binary = std::string("1.0 0 0 0 0 0 0 1\n") + std::string("\0\x01\x02", 3);
  try {
    io::import_tum(binary, "blob.bin");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_TRUE(starts_with(e.what(), "blob.bin: not a text file (a NUL byte at offset 18)")) << e.what();
  }
  try {
    io::import_csv_ranges(std::string("\xFF\xFE" "0\0.\0" "1\0", 8), "wide.csv");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_TRUE(starts_with(e.what(), "wide.csv: UTF-16 text; save it as UTF-8")) << e.what();
  }
  EXPECT_THROW(io::import_carmen(binary, "blob.bin"), InputError);
  EXPECT_THROW(io::import_breezyslam(binary, "blob.bin"), InputError);
  EXPECT_THROW(io::import_csv_ranges(binary, "blob.bin"), InputError);
}

TEST(ImportChecks, ReadImportTextRefusesDevicesFoldersAndLargeFiles) {
  TestFolder folder;
  const auto message = [](const std::string& path, std::uint64_t limit) {
    try {
      io::read_import_text(path, limit);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_TRUE(starts_with(message("/dev/zero", io::kMaxImportBytes), "/dev/zero: not a regular file"))
      << message("/dev/zero", io::kMaxImportBytes);
  EXPECT_TRUE(starts_with(message(folder.path().string(), io::kMaxImportBytes), folder.path().string() + ": "));
  EXPECT_TRUE(starts_with(message(folder / "missing.txt", io::kMaxImportBytes), folder / "missing.txt: cannot open"));
  const std::string big = folder.write("big.txt", std::string(2000, 'x'));
  EXPECT_TRUE(starts_with(message(big, 1000), big + ": 2000 bytes, more than the import limit of 1000"))
      << message(big, 1000);
  const std::string blob = folder.write("blob.bin", std::string("abc\0def", 7));
  EXPECT_TRUE(starts_with(message(blob, io::kMaxImportBytes), blob + ": not a text file")) << message(blob, 1000);
  const std::string good = folder.write("good.txt", "1.0 0 0 0 0 0 0 1\n");
  EXPECT_EQ(io::read_import_text(good, io::kMaxImportBytes), "1.0 0 0 0 0 0 0 1\n");
  EXPECT_EQ(io::read_import_text(folder.write("empty.txt", ""), io::kMaxImportBytes), "");
}

TEST(WriteImported, WritesAScanLogAndPoseFileThatReadBack) {
  TestFolder folder;
  io::BreezySlamImportOptions options;
  options.values_per_scan = 4;
  const std::string text = breezyslam_line(5000000, 0, 0, 4, 1234) + breezyslam_line(5100000, 100, 120, 4, 7);
  const io::ImportedData data = io::import_breezyslam(text, "r.dat", options);
  io::write_imported(data, folder / "r.log", folder / "r.poses", "r.dat");
  const io::ScanLog log = io::read_scan_log(folder / "r.log");
  EXPECT_TRUE(log.damage.empty()) << log.damage;
  ASSERT_EQ(log.scans.size(), 2u);
  EXPECT_EQ(log.scans[1].raw.values_mm, (std::vector<std::uint32_t>{7, 7, 7, 7}));
  EXPECT_EQ(log.scans[1].host_time_s, 5.1);
  EXPECT_EQ(log.parameters, data.sensor);
  const auto poses = io::read_pose_file(folder / "r.poses");
  ASSERT_EQ(poses.size(), 2u);
  EXPECT_EQ(poses[1].pose.yaw_rad, data.poses[1].pose.yaw_rad);  // written exactly
  // Nothing but the two outputs in the folder: no temporary file left.
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(folder.path()), {}), 2);
  EXPECT_THROW(io::write_imported(data, folder / "missing/r.log", folder / "p", "r.dat"), InputError);
}

}  // namespace
}  // namespace stridemap
