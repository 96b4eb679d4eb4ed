#pragma once
// The 256 colours of a ColourScale, as OpenCV's colour maps give them (BGR
// order), shared by the flat map renderer and the 3D terrain view so that
// both draw a value in the same colour.
#include <algorithm>
#include <array>
#include <cstdint>
#include <opencv2/imgproc.hpp>

#include "stridemap/render/grid_render.hpp"

namespace stridemap::io::detail {

inline std::array<cv::Vec3b, 256> colour_scale_bgr(ColourScale scale) {
  if (scale == ColourScale::diverging) {
    // Blue, white, red (RGB anchors), linear between: white is zero error.
    constexpr double anchors[5][3] = {{33, 76, 166}, {102, 153, 217}, {247, 247, 247}, {230, 122, 97}, {178, 23, 31}};
    std::array<cv::Vec3b, 256> palette{};
    for (int i = 0; i < 256; ++i) {
      const double x = i / 255.0 * 4.0;
      const int k = std::min(static_cast<int>(x), 3);
      const double f = x - k;
      const auto mix = [&](int c) { return cv::saturate_cast<std::uint8_t>(anchors[k][c] * (1 - f) + anchors[k + 1][c] * f); };
      palette[static_cast<std::size_t>(i)] = cv::Vec3b(mix(2), mix(1), mix(0));
    }
    return palette;
  }
  int map = cv::COLORMAP_VIRIDIS;
  if (scale == ColourScale::turbo) map = cv::COLORMAP_TURBO;
  if (scale == ColourScale::cividis) map = cv::COLORMAP_CIVIDIS;
  cv::Mat ramp(1, 256, CV_8UC1);
  for (int i = 0; i < 256; ++i) ramp.at<std::uint8_t>(0, i) = static_cast<std::uint8_t>(i);
  cv::Mat bgr;
  cv::applyColorMap(ramp, bgr, map);
  std::array<cv::Vec3b, 256> palette{};
  for (int i = 0; i < 256; ++i) palette[static_cast<std::size_t>(i)] = bgr.at<cv::Vec3b>(0, i);
  return palette;
}

}  // namespace stridemap::io::detail
