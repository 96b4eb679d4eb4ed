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

}  // namespace
}  // namespace stridemap
