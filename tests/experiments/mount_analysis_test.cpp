#include "stridemap/experiments/mount_analysis.hpp"

#include <cmath>
#include <numbers>
#include <string>

#include <gtest/gtest.h>

#include "stridemap/core/error.hpp"
#include "stridemap/experiments/urg_walk_sensor.hpp"

namespace stridemap {
namespace mount_analysis_test {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

MountSensorFactory urg_factory() {
  return [](const Scene& scene, const NamedMount& mount, const UpdateOptions& update) -> std::unique_ptr<WalkSensor> {
    UrgWalkSensorOptions o;
    o.mount = mount.mount;
    return std::make_unique<UrgWalkSensor>(scene, o, update, 1);
  };
}

MountRangeShare urg_share() {
  return [](const NamedMount& m) -> std::optional<double> { return urg_share_in_range_interval(m.mount, UrgParameters{}); };
}

MountAnalysisOptions small_sweep() {
  MountAnalysisOptions o;
  o.fields = 1;
  o.sweep_heights_m = {0.26};
  o.sweep_pitches_rad = {35.0 * kDeg, 89.0 * kDeg};
  return o;
}

// Section 4.2's argument, measured: the low mount (Fig. 7a) leaves the most
// ground unseen, the high shallow one (7b) sees its obstacles from farther
// and with larger errors, the chosen one (7c) sees most and keeps its ranges
// in the URG's best interval.
TEST(MountAnalysis, ThePapersUrgMountsRankAsSectionFourTwoArgues) {
  const MountAnalysisResult r = run_mount_analysis(paper_urg_mounts(), urg_factory(), urg_share(), small_sweep());
  ASSERT_EQ(r.named.size(), 3u);
  const MountMetrics &a = r.named[0], &b = r.named[1], &c = r.named[2];
  EXPECT_EQ(a.mount.name, "fig7a");
  for (const MountMetrics* m : {&a, &b, &c}) {
    EXPECT_TRUE(m->sees_ground);
    EXPECT_GT(m->ground_cells, 1000u);
    EXPECT_GT(m->unobserved_fraction, 0.0);
    EXPECT_LT(m->unobserved_fraction, 1.0);
  }
  EXPECT_GT(a.unobserved_fraction, c.unobserved_fraction);
  EXPECT_GT(b.unobserved_fraction, c.unobserved_fraction);
  EXPECT_GT(b.mean_height_uncertainty_m, c.mean_height_uncertainty_m);
  EXPECT_GT(b.look_ahead_m, c.look_ahead_m);  // a steeper pitch looks less far ahead
  EXPECT_GT(*c.favourable_range_share, *b.favourable_range_share);
  EXPECT_GT(*b.favourable_range_share, *a.favourable_range_share);
  EXPECT_GT(c.score, a.score);
  EXPECT_GT(c.score, b.score);
  // The sweep's 26 cm / 35 deg is fig7c again; 89 deg looks at its feet.
  ASSERT_EQ(r.sweep.size(), 2u);
  EXPECT_DOUBLE_EQ(r.sweep[0].unobserved_fraction, c.unobserved_fraction);
  EXPECT_EQ(r.sweep[1].score, 0.0);
  EXPECT_EQ(r.best, 0u);
}

TEST(MountAnalysis, RangeShareFollowsTheGeometry) {
  // 26 cm / 35 deg: the beam ahead meets the ground (-0.10 to +0.15 m)
  // between 0.19 and 0.63 m; only the highest surfaces come closer than
  // 0.2 m.
  const double chosen = urg_share_in_range_interval(SensorMount{0.26, 35 * kDeg, 0, 0}, UrgParameters{});
  EXPECT_GT(chosen, 0.9);
  EXPECT_LT(chosen, 1.0);
  // 16 cm / 15 deg: ground ahead at 0.62 m, lower surfaces beyond 0.9 m.
  const double low = urg_share_in_range_interval(SensorMount{0.16, 15 * kDeg, 0, 0}, UrgParameters{});
  EXPECT_LT(low, chosen);
  // Looking up, the sensor meets no surface below it.
  EXPECT_EQ(urg_share_in_range_interval(SensorMount{0.26, -20 * kDeg, 0, 0}, UrgParameters{}), 0.0);
}

TEST(MountAnalysis, BadInputIsRejectedBeforeAnyWalk) {
  MountAnalysisOptions o = small_sweep();
  o.sweep_heights_m.clear();
  try {
    run_mount_analysis(paper_urg_mounts(), urg_factory(), urg_share(), o);
    FAIL() << "an empty sweep grid was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("the sweep grid is empty"), std::string::npos) << e.what();
  }
  o = small_sweep();
  o.sweep_pitches_rad = {95.0 * kDeg};
  EXPECT_THROW(run_mount_analysis(paper_urg_mounts(), urg_factory(), urg_share(), o), InputError);
  o = small_sweep();
  o.fields = 0;
  EXPECT_THROW(run_mount_analysis(paper_urg_mounts(), urg_factory(), urg_share(), o), InputError);

  const auto named_error = [&](SensorMount mount) {
    try {
      run_mount_analysis({{"mine", mount, std::nullopt}}, urg_factory(), urg_share(), small_sweep());
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(named_error({-0.1, 35 * kDeg, 0, 0}).find("sensor mount mine: height"), std::string::npos);
  EXPECT_NE(named_error({0.26, 100 * kDeg, 0, 0}).find("past vertical"), std::string::npos);
  EXPECT_NE(named_error({0.26, -10 * kDeg, 0, 0}).find("cannot see the ground"), std::string::npos);
}

}  // namespace
}  // namespace mount_analysis_test
}  // namespace stridemap
