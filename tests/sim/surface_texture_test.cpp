#include "stridemap/sim/surface_texture.hpp"

#include <cmath>

#include <gtest/gtest.h>

#include "stridemap/core/error.hpp"

namespace stridemap {
namespace {

TEST(SurfaceTexture, GainsHaveMeanOneAndTheConfiguredLogSpread) {
  const SurfaceTexture texture;
  const double sigma = texture.options().log_sigma;
  const int n = 20000;
  double sum = 0.0, log_sum = 0.0, log_squares = 0.0;
  for (int i = 0; i < n; ++i) {
    const double g = texture.gain(Eigen::Vector3d(0.0021 * i, 0.37, 0.0), -1);
    ASSERT_GT(g, 0.0);
    sum += g;
    log_sum += std::log(g);
    log_squares += std::log(g) * std::log(g);
  }
  const double log_mean = log_sum / n;
  EXPECT_NEAR(sum / n, 1.0, 0.02);
  EXPECT_NEAR(log_mean, -0.5 * sigma * sigma, 0.02);
  EXPECT_NEAR(std::sqrt(log_squares / n - log_mean * log_mean), sigma, 0.01);
}

TEST(SurfaceTexture, APlaceKeepsItsGainAndGrainsDiffer) {
  const SurfaceTexture texture;
  const Eigen::Vector3d p(0.8031, -0.1102, 0.1);
  EXPECT_EQ(texture.gain(p, 0), texture.gain(p, 0));
  // The same grain: within one 2 mm cube.
  EXPECT_EQ(texture.gain(p, 0), texture.gain(p + Eigen::Vector3d(0.0002, 0.0001, 0.0), 0));
  // Another object, or a cube further on, is another grain.
  EXPECT_NE(texture.gain(p, 0), texture.gain(p, 1));
  EXPECT_NE(texture.gain(p, 0), texture.gain(p + Eigen::Vector3d(0.004, 0.0, 0.0), 0));
  SurfaceTextureOptions other;
  other.salt = 7;
  EXPECT_NE(texture.gain(p, 0), SurfaceTexture(other).gain(p, 0));
}

TEST(SurfaceTexture, ZeroSpreadIsUniformAndFarPointsAreFinite) {
  SurfaceTextureOptions options;
  options.log_sigma = 0.0;
  EXPECT_EQ(SurfaceTexture(options).gain(Eigen::Vector3d(1.0, 2.0, 3.0), 4), 1.0);
  const double far = SurfaceTexture().gain(Eigen::Vector3d(1e300, -1e300, 0.0), -1);
  EXPECT_TRUE(std::isfinite(far));
}

TEST(SurfaceTexture, RejectsBadOptions) {
  SurfaceTextureOptions options;
  options.log_sigma = -0.1;
  EXPECT_THROW(SurfaceTexture{options}, InputError);
  options.log_sigma = std::nan("");
  EXPECT_THROW(SurfaceTexture{options}, InputError);
  options = {};
  options.grain_m = 0.0;
  try {
    SurfaceTexture{options};
    FAIL() << "a zero grain was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("grain_m"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace stridemap
