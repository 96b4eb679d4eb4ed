#include "stridemap/mapfile/detail/settings_json.hpp"

namespace stridemap::io::detail {

using nlohmann::json;

json mount_json(const SensorMount& m) {
  return {{"height_m", m.height_m},
          {"pitch_rad", m.pitch_rad},
          {"forward_offset_m", m.forward_offset_m},
          {"lateral_offset_m", m.lateral_offset_m}};
}

json mapper_settings_json(const MapperConfig& c) {
  const MapperOptions& m = c.mapper;
  const UpdateOptions& u = m.update;
  return {
      {"mount", mount_json(c.mount)},
      {"map",
       {{"cells_per_side", m.grid.cells_per_side},
        {"cell_size_m", m.grid.cell_size_m},
        {"follow_robot", m.follow_robot},
        {"window_ahead_m", m.window_ahead_m},
        {"reject_stale_scans", m.reject_stale_scans}}},
      {"update",
       {{"certainty_increment", u.certainty_increment},
        {"certainty_max", u.certainty_max},
        {"max_pitch_error_rad", u.max_pitch_error_rad},
        {"max_roll_error_rad", u.max_roll_error_rad},
        {"max_mount_pitch_error_rad", u.max_mount_pitch_error_rad},
        {"use_turning_term", u.use_turning_term},
        {"elevation_rule", u.elevation_rule == ElevationRule::gated_highest ? "gated" : "paper"},
        {"replace_after_contradictions", u.replace_after_contradictions}}},
      {"fill",
       {{"window_radius_cells", c.fill.window_radius_cells},
        {"min_known_neighbours", c.fill.min_known_neighbours},
        {"min_quadrants", c.fill.min_quadrants},
        {"near_weight", c.fill.near_weight},
        {"max_quartile_spread_m", c.fill.max_quartile_spread_m}}},
      {"range_calibration", {{"coefficients", c.calibration.coefficients}}},
      {"foothold",
       {{"enabled", c.foothold.enabled},
        {"foot_radius_m", c.foothold.foot_radius_m},
        {"max_slope_deg", c.foothold.max_slope_deg},
        {"max_step_m", c.foothold.max_step_m},
        {"max_roughness_m", c.foothold.max_roughness_m},
        {"edge_search_radius_m", c.foothold.edge_search_radius_m},
        {"edge_clearance_m", c.foothold.edge_clearance_m},
        {"full_certainty", c.foothold.full_certainty},
        {"min_known_fraction", c.foothold.min_known_fraction},
        {"safe_score", c.foothold.safe_score}}},
      {"height_fusion",
       {{"enabled", c.height_fusion.enabled},
        {"mahalanobis_gate", c.height_fusion.mahalanobis_gate},
        {"outlier_variance_m2", c.height_fusion.outlier_variance_m2},
        {"min_variance_m2", c.height_fusion.min_variance_m2},
        {"sigma_per_uncertainty", c.height_fusion.sigma_per_uncertainty}}},
  };
}

json run_settings_json(const std::string& filters, MapFilter map_filter, const std::optional<std::string>& clock) {
  json settings = {{"filters", filters}, {"map_filter", std::string(map_filter_name(map_filter))}};
  if (clock) settings["clock"] = *clock;
  return settings;
}

}  // namespace stridemap::io::detail
