// Host time of a scan from the sensor clock: the minimum link delay over a
// window, so the jitter of the receive time disappears.
#include <gtest/gtest.h>

#include <random>

#include "stridemap/sensors/scan_clock.hpp"

namespace stridemap {
namespace {

TEST(ScanClock, JitterDisappearsAndTheFixedDelayIsRemoved) {
  ScanClock clock(50, 0.1);
  std::mt19937_64 rng(7);
  std::exponential_distribution<double> jitter(1.0 / 0.004);  // USB and scheduling delays, mean 4 ms
  const double offset = 1.7e9;
  double worst = 0.0;
  for (int k = 0; k < 300; ++k) {
    const double sensor = 0.1 * k;
    const double host = sensor + offset + 0.1 + 0.0005 + jitter(rng);  // sent at the end of the turn
    const double estimate = clock.add(sensor, host);
    if (k >= 50) worst = std::max(worst, std::abs(estimate - (sensor + offset)));
  }
  EXPECT_LT(worst, 0.0015);  // the fixed 0.5 ms plus the smallest jitter of the window
}

TEST(ScanClock, WindowFollowsADriftingClock) {
  ScanClock clock(20, 0.0);
  for (int k = 0; k < 200; ++k) clock.add(0.1 * k, 0.1 * k * (1.0 + 1e-3));  // 1000 ppm fast
  EXPECT_NEAR(clock.offset_s(), 0.1 * 199 * 1e-3, 0.1 * 20 * 1e-3);
  clock.reset();
  EXPECT_EQ(clock.offset_s(), 0.0);
}

// The first scans of a stream read in one go (found by the scip_driver
// fuzzer): each is a new minimum of the delay, and without a limit the
// second got exactly the first one's host time.
TEST(ScanClock, ScansReadTogetherKeepIncreasingHostTimesAndTheEstimateCatchesUp) {
  ScanClock clock(100, 0.1);
  const double offset = 1.7e9, read_at = offset + 0.5;
  double previous = clock.add(0.0, read_at);
  for (int k = 1; k < 4; ++k) {  // three more frames that waited in the same buffer
    const double host = clock.add(0.1 * k, read_at);
    EXPECT_GT(host, previous) << "scan " << k;
    EXPECT_GE(host - previous, 0.05 - 1e-6);  // doubles near 1.7e9 s step by 2.4e-7 s
    previous = host;
  }
  // From now on each frame is read as it comes, 1 ms after its turn ends.
  for (int k = 4; k < 40; ++k) {
    const double host = clock.add(0.1 * k, offset + 0.1 * k + 0.1 + 0.001);
    EXPECT_GT(host, previous) << "scan " << k;
    previous = host;
  }
  EXPECT_NEAR(previous, offset + 3.9, 0.0015);  // caught up with the true offset
}

}  // namespace
}  // namespace stridemap
