#include "stridemap/config/mapper_config.hpp"

#include <cmath>
#include <numbers>

#include "strict_yaml.hpp"

namespace stridemap {
namespace {

using namespace io_detail;

constexpr double kDeg = std::numbers::pi / 180.0;

class MapperConfigReader : public StrictYamlReader {
 public:
  using StrictYamlReader::StrictYamlReader;

  MapperConfig read(const YAML::Node& root) {
    MapperConfig config;
    if (!root.IsDefined() || root.IsNull()) return config;  // an empty file: all defaults
    const Fields top = read_map(root, "", {"mount", "map", "update", "fill", "range_calibration", "foothold",
                                            "visibility", "global_map", "height_fusion"});
    if (const Field* f = find(top, "mount")) read_mount(f->value, config.mount);
    if (const Field* f = find(top, "map")) read_map_section(f->value, config.mapper);
    if (const Field* f = find(top, "update")) read_update(f->value, config.mapper.update);
    if (const Field* f = find(top, "fill")) read_fill(f->value, config.fill);
    if (const Field* f = find(top, "range_calibration")) read_calibration(f->value, config.calibration);
    if (const Field* f = find(top, "foothold")) read_foothold(f->value, config.foothold);
    if (const Field* f = find(top, "visibility")) read_visibility(f->value, config.visibility);
    if (const Field* f = find(top, "global_map")) read_global_map(f->value, config.global_map);
    if (const Field* f = find(top, "height_fusion")) read_height_fusion(f->value, config.height_fusion);
    return config;
  }

 private:
  // A number with a check; `rule` says what is expected when it fails.
  template <typename Check>
  double checked(const Fields& fields, const YAML::Node& node, const std::string& path, const char* name,
                 double default_value, Check check, const char* rule) {
    const double value = number(fields, node, path, name, default_value);
    if (!std::isfinite(value) || !check(value)) {
      fail_at(join(path, name), std::string("expected ") + rule + ", got " + std::to_string(value));
    }
    return value;
  }
  int whole(const Fields& fields, const YAML::Node& node, const std::string& path, const char* name, int default_value,
            int lo, int hi) {
    const std::uint64_t value = whole_number(fields, node, path, name, static_cast<std::uint64_t>(default_value));
    if (value < static_cast<std::uint64_t>(lo) || value > static_cast<std::uint64_t>(hi)) {
      fail_at(join(path, name), "expected a whole number from " + std::to_string(lo) + " to " + std::to_string(hi) +
                                    ", got " + std::to_string(value));
    }
    return static_cast<int>(value);
  }

  static bool positive(double v) { return v > 0.0; }
  static bool non_negative(double v) { return v >= 0.0; }
  static bool any(double) { return true; }

  // A quantity that has an old key (the paper's names) and a new one (the
  // rigid transform's names): giving both is an error, not a silent choice.
  void reject_both(const Fields& f, const std::string& p, const char* old_key, const char* new_key) {
    const Field* old_field = find(f, old_key);
    const Field* new_field = find(f, new_key);
    if (old_field && new_field) {
      fail(new_field->key, join(p, new_key),
           std::string("gives the same quantity as ") + old_key + " on line " + std::to_string(line_of(old_field->key)) +
               "; keep one of them");
    }
  }

  void read_mount(const YAML::Node& node, SensorMount& m) {
    const std::string p = "mount";
    const Fields f = read_map(node, p,
                              {"height_m", "pitch_deg", "forward_offset_m", "lateral_offset_m", "x_m", "y_m", "z_m",
                               "roll_deg", "yaw_deg"});
    reject_both(f, p, "height_m", "z_m");
    reject_both(f, p, "forward_offset_m", "x_m");
    reject_both(f, p, "lateral_offset_m", "y_m");
    // height_m is the paper's d_z, a height above the ground; z_m is the
    // rigid transform's offset above the trunk reference point, which may
    // lie below it (docs/config.md).
    m.height_m = find(f, "z_m") ? checked(f, node, p, "z_m", m.height_m, any, "a finite number")
                                : checked(f, node, p, "height_m", m.height_m, positive, "a height above the ground > 0 m");
    m.pitch_rad = kDeg * checked(f, node, p, "pitch_deg", m.pitch_rad / kDeg,
                                 [](double v) { return v > -90.0 && v < 90.0; }, "a pitch strictly between -90 and 90 deg");
    const char* forward = find(f, "x_m") ? "x_m" : "forward_offset_m";
    const char* lateral = find(f, "y_m") ? "y_m" : "lateral_offset_m";
    m.forward_offset_m = checked(f, node, p, forward, m.forward_offset_m, any, "a finite number");
    m.lateral_offset_m = checked(f, node, p, lateral, m.lateral_offset_m, any, "a finite number");
    const auto half_turn = [](double v) { return v >= -180.0 && v <= 180.0; };
    m.roll_rad = kDeg * checked(f, node, p, "roll_deg", m.roll_rad / kDeg, half_turn, "a roll from -180 to 180 deg");
    m.yaw_rad = kDeg * checked(f, node, p, "yaw_deg", m.yaw_rad / kDeg, half_turn, "a yaw from -180 to 180 deg");
  }

  void read_map_section(const YAML::Node& node, MapperOptions& o) {
    const std::string p = "map";
    const Fields f =
        read_map(node, p, {"cells_per_side", "cell_size_m", "follow_robot", "window_ahead_m", "reject_stale_scans"});
    o.grid.cells_per_side = whole(f, node, p, "cells_per_side", o.grid.cells_per_side, 1, kMaxGridCellsPerSide);
    o.grid.cell_size_m = checked(f, node, p, "cell_size_m", o.grid.cell_size_m,
                                 [](double v) { return v >= kMinCellSizeM && v <= kMaxCellSizeM; },
                                 "a cell size from 0.0001 to 10 m");
    o.follow_robot = boolean(f, node, p, "follow_robot", o.follow_robot);
    o.window_ahead_m = checked(f, node, p, "window_ahead_m", o.window_ahead_m, any, "a finite number");
    o.reject_stale_scans = boolean(f, node, p, "reject_stale_scans", o.reject_stale_scans);
  }

  void read_update(const YAML::Node& node, UpdateOptions& u) {
    const std::string p = "update";
    const Fields f = read_map(node, p,
                              {"certainty_increment", "certainty_max", "max_pitch_error_deg", "max_roll_error_deg",
                               "max_mount_pitch_error_deg", "use_turning_term", "elevation_rule",
                               "replace_after_contradictions"});
    u.certainty_increment =
        checked(f, node, p, "certainty_increment", u.certainty_increment, positive, "a number > 0");
    u.certainty_max = checked(f, node, p, "certainty_max", u.certainty_max,
                              [&](double v) { return v >= u.certainty_increment; },
                              "a number >= certainty_increment");
    u.max_pitch_error_rad =
        kDeg * checked(f, node, p, "max_pitch_error_deg", u.max_pitch_error_rad / kDeg, non_negative, "an angle >= 0");
    u.max_roll_error_rad =
        kDeg * checked(f, node, p, "max_roll_error_deg", u.max_roll_error_rad / kDeg, non_negative, "an angle >= 0");
    u.max_mount_pitch_error_rad = kDeg * checked(f, node, p, "max_mount_pitch_error_deg",
                                                 u.max_mount_pitch_error_rad / kDeg, non_negative, "an angle >= 0");
    u.use_turning_term = boolean(f, node, p, "use_turning_term", u.use_turning_term);
    if (find(f, "elevation_rule")) {
      const std::string rule = text(f, node, p, "elevation_rule");
      try {
        u.elevation_rule = parse_enum_name<ElevationRule>(rule);
      } catch (const InputError& e) {
        fail_at(join(p, "elevation_rule"), e.what());
      }
    }
    u.replace_after_contradictions =
        whole(f, node, p, "replace_after_contradictions", u.replace_after_contradictions, 1, 255);
  }

  void read_fill(const YAML::Node& node, FillOptions& o) {
    const std::string p = "fill";
    const Fields f = read_map(node, p,
                              {"window_radius_cells", "min_known_neighbours", "min_quadrants", "near_weight",
                               "max_quartile_spread_m"});
    o.window_radius_cells = whole(f, node, p, "window_radius_cells", o.window_radius_cells, 1, 7);
    o.min_known_neighbours = whole(f, node, p, "min_known_neighbours", o.min_known_neighbours, 1, 224);
    o.min_quadrants = whole(f, node, p, "min_quadrants", o.min_quadrants, 1, 4);
    o.near_weight = checked(f, node, p, "near_weight", o.near_weight, positive, "a weight > 0");
    o.max_quartile_spread_m =
        checked(f, node, p, "max_quartile_spread_m", o.max_quartile_spread_m, any, "a finite number (<= 0: off)");
  }

  void read_foothold(const YAML::Node& node, FootholdOptions& o) {
    const std::string p = "foothold";
    const Fields f = read_map(node, p,
                              {"enabled", "update_every_scan", "foot_radius_m", "max_slope_deg", "max_step_m",
                               "max_roughness_m",
                               "edge_search_radius_m", "edge_clearance_m", "full_certainty", "min_known_fraction",
                               "safe_score"});
    o.enabled = boolean(f, node, p, "enabled", o.enabled);
    o.update_every_scan = boolean(f, node, p, "update_every_scan", o.update_every_scan);
    o.foot_radius_m = checked(f, node, p, "foot_radius_m", o.foot_radius_m, positive, "a radius > 0 m");
    o.max_slope_deg = checked(f, node, p, "max_slope_deg", o.max_slope_deg,
                              [](double v) { return v > 0.0 && v <= 90.0; }, "an angle > 0 and <= 90 deg");
    o.max_step_m = checked(f, node, p, "max_step_m", o.max_step_m, positive, "a height > 0 m");
    o.max_roughness_m = checked(f, node, p, "max_roughness_m", o.max_roughness_m, positive, "a length > 0 m");
    o.edge_search_radius_m =
        checked(f, node, p, "edge_search_radius_m", o.edge_search_radius_m, non_negative, "a radius >= 0 m");
    o.edge_clearance_m = checked(f, node, p, "edge_clearance_m", o.edge_clearance_m, non_negative, "a length >= 0 m");
    o.full_certainty = checked(f, node, p, "full_certainty", o.full_certainty, positive, "a number > 0");
    const auto fraction = [](double v) { return v >= 0.0 && v <= 1.0; };
    o.min_known_fraction =
        checked(f, node, p, "min_known_fraction", o.min_known_fraction, fraction, "a fraction from 0 to 1");
    o.safe_score = checked(f, node, p, "safe_score", o.safe_score, fraction, "a score from 0 to 1");
  }

  void read_global_map(const YAML::Node& node, GlobalMapOptions& o) {
    const std::string p = "global_map";
    const Fields f = read_map(node, p, {"folder", "tile_cells", "cached_tiles", "save_interval_s"});
    if (find(f, "folder")) o.folder = text(f, node, p, "folder");
    o.tile_cells = whole(f, node, p, "tile_cells", o.tile_cells, 1, kMaxGridCellsPerSide);
    o.cached_tiles = whole(f, node, p, "cached_tiles", o.cached_tiles, 1, 1024);
    o.save_interval_s = checked(f, node, p, "save_interval_s", o.save_interval_s,
                                [](double v) { return v >= 0.0 && v <= 86400.0; }, "seconds from 0 to 86400");
  }

  void read_visibility(const YAML::Node& node, VisibilityOptions& o) {
    const std::string p = "visibility";
    const Fields f = read_map(node, p,
                              {"enabled", "uncertainty_factor", "relief_factor", "certainty_decrement",
                               "beam_spacing_cells"});
    o.enabled = boolean(f, node, p, "enabled", o.enabled);
    o.uncertainty_factor =
        checked(f, node, p, "uncertainty_factor", o.uncertainty_factor, non_negative, "a factor >= 0");
    o.relief_factor = checked(f, node, p, "relief_factor", o.relief_factor, non_negative, "a factor >= 0 (cells)");
    o.certainty_decrement =
        checked(f, node, p, "certainty_decrement", o.certainty_decrement, positive, "a certainty > 0");
    o.beam_spacing_cells = checked(f, node, p, "beam_spacing_cells", o.beam_spacing_cells,
                                   [](double v) { return v >= 0.0 && v <= 1000.0; }, "a spacing from 0 to 1000 cells");
  }

  void read_height_fusion(const YAML::Node& node, HeightFusionOptions& o) {
    const std::string p = "height_fusion";
    const Fields f = read_map(node, p,
                              {"enabled", "mahalanobis_gate", "outlier_variance_m2", "min_variance_m2",
                               "sigma_per_uncertainty"});
    o.enabled = boolean(f, node, p, "enabled", o.enabled);
    o.mahalanobis_gate = checked(f, node, p, "mahalanobis_gate", o.mahalanobis_gate, positive, "a number of sigmas > 0");
    o.outlier_variance_m2 =
        checked(f, node, p, "outlier_variance_m2", o.outlier_variance_m2, positive, "a variance > 0 [m^2]");
    o.min_variance_m2 = checked(f, node, p, "min_variance_m2", o.min_variance_m2, positive, "a variance > 0 [m^2]");
    o.sigma_per_uncertainty =
        checked(f, node, p, "sigma_per_uncertainty", o.sigma_per_uncertainty, positive, "a factor > 0");
  }

  void read_calibration(const YAML::Node& node, RangeCalibration& c) {
    const std::string p = "range_calibration";
    const Fields f = read_map(node, p, {"coefficients"});
    const Field* coefficients = find(f, "coefficients");
    if (!coefficients) fail(node, join(p, "coefficients"), "required field is missing");
    const std::string cp = join(p, "coefficients");
    const YAML::Node& list = coefficients->value;
    if (!list.IsSequence() || list.size() != 4) {
      fail(list.IsNull() ? coefficients->key : list, cp, "expected a list of 4 numbers [c0, c1, c2, c3], got " + describe(list));
    }
    for (std::size_t k = 0; k < 4; ++k) {
      const YAML::Node item = list[k];
      const std::string ip = cp + "[" + std::to_string(k) + "]";
      double value = 0.0;
      try {
        if (!item.IsScalar() || item.Tag() == "!") throw YAML::Exception(item.Mark(), "not a number");
        value = item.as<double>();
      } catch (const YAML::Exception&) {
        fail(item, ip, "expected a number, got " + describe(item));
      }
      if (!std::isfinite(value)) fail(item, ip, "expected a finite number");
      c.coefficients[k] = value;
    }
  }
};

}  // namespace

MapperConfig parse_mapper_config(const std::string& text, const std::string& source_name) {
  return MapperConfigReader(source_name).read(load_single_document(text, source_name));
}

MapperConfig load_mapper_config(const std::string& path) {
  return parse_mapper_config(read_text_file(path, "mapper configuration"), path);
}

}  // namespace stridemap
