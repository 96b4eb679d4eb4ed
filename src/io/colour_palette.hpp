#pragma once
// The 256 colours of a ColourScale, as OpenCV's colour maps give them (BGR
// order), shared by the flat map renderer and the 3D terrain view so that
// both draw a value in the same colour.
#include <array>
#include <cstdint>
#include <opencv2/imgproc.hpp>

#include "stridemap/io/grid_render.hpp"

namespace stridemap::io::detail {

inline std::array<cv::Vec3b, 256> colour_scale_bgr(ColourScale scale) {
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
