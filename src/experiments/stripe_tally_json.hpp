#pragma once
// The stripe tally as the summaries write it: one wording for the cart-rail
// and lighting summaries (docs/outputs.md).
#include <nlohmann/json.hpp>

#include "stridemap/experiments/cart_rail.hpp"

namespace stridemap::detail {

inline void add_stripe_tally(nlohmann::json& out, const StripeTally& t) {
  out["truth_visible_columns"] = t.truth_visible;
  out["detected_columns"] = t.detected;
  out["correct_columns"] = t.correct;
  out["false_detections"] = t.false_detections;
  out["detection_rate"] = t.detection_rate();
  out["false_rate"] = t.false_rate();
  out["false_hidden_on_true_row"] = t.hidden_on_true_row;
  out["false_off_row_rate"] = t.off_row_rate();
  out["false_off_surface"] = t.off_surface;
  out["false_off_surface_rate"] = t.off_surface_rate();
  out["false_no_laser_light"] = t.no_laser_light;
  out["false_no_laser_light_rate"] = t.no_laser_light_rate();
  out["row_error_rms_px"] = t.row_error_rms_px;
  out["map_points"] = t.map_points;
}

}  // namespace stridemap::detail
