#include "stridemap/live/map_report.hpp"

#include <cstdio>
#include <filesystem>

#include <nlohmann/json.hpp>

#include "stridemap/core/cas_filter.hpp"
#include "stridemap/core/grid_map.hpp"
#include "stridemap/io/output_folder.hpp"
#include "stridemap/mapfile/detail/settings_json.hpp"
#include "stridemap/mapfile/map_file.hpp"
#include "stridemap/io/text_file.hpp"

namespace stridemap {

std::string map_summary_json(const ScanMapper& mapper, const ExportedMap& layers,
                             const scip::ScipParameters& sensor, const MapRunInfo& info, const LiveRunStats* live) {
  using nlohmann::json;
  const ScanMapperStats& s = mapper.stats();
  const MapperTotals& t = mapper.mapper().totals();
  std::size_t measured = 0, filled = 0;
  const CellMask& states = layers.state();
  for (Eigen::Index i = 0; i < states.size(); ++i) {
    const auto state = static_cast<CellState>(states.data()[i]);
    measured += state == CellState::measured;
    filled += state == CellState::filled;
  }
  json summary = {
      {"command", info.command},
      {"scans_from", info.scans_from},
      {"poses_from", info.poses_from},
      {"resumed_from", info.resumed_from.empty() ? json(nullptr) : json(info.resumed_from)},
      {"sensor",
       {{"model", sensor.model},
        {"dmin_mm", sensor.min_distance_mm},
        {"dmax_mm", sensor.max_distance_mm},
        {"ares", sensor.steps_per_turn},
        {"amin", sensor.first_step},
        {"amax", sensor.last_step},
        {"afrt", sensor.front_step},
        {"scan_rpm", sensor.motor_speed_rpm}}},
      {"scans",
       {{"received", s.scans},
        {"integrated", s.integrated},
        {"mapped", scans_mapped(mapper)},
        {"rejected_for_time", t.scans_rejected_for_time},
        {"rejected_for_pose", t.scans_rejected_for_pose},
        {"before_first_pose", s.before_first_pose},
        {"after_last_pose", s.after_last_pose},
        {"pose_gap", s.pose_gap},
        {"rejected", s.rejected}}},
      {"beams",
       {{"valid", s.beams.valid},
        {"error_codes", s.beams.error_codes},
        {"beyond_max_range", s.beams.beyond_max_range},
        {"integrated", t.integrated},
        {"implausible", t.implausible},
        {"outside_map", t.outside_map}}},
      {"map",
       {{"coverage", map_coverage(layers)},
        {"measured_cells", measured},
        {"filled_cells", filled},
        {"cells_per_side", layers.state().rows()},
        {"cell_size_m", layers.cell_size_m},
        {"min_cell", {layers.min_cell.x, layers.min_cell.y}}}}};
  // The keys sort as a whole, so where the settings join makes no difference to the text.
  summary.update(io::detail::run_settings_json(scan_filter_list_name(mapper.options().filters), info.map_filter,
                                               info.clock));
  if (!info.log_damage.empty()) summary["log_damage"] = info.log_damage;
  if (info.log_lines_skipped > 0) summary["log_lines_skipped"] = info.log_lines_skipped;
  if (!info.log_stop.empty()) summary["log_stop"] = info.log_stop;
  summary["pose_lines_skipped"] = info.pose_lines_skipped;
  if (live != nullptr) {
    const UrgDriverStats& d = live->driver;
    summary["run"] = {{"duration_s", live->duration_s},
                      {"cpu_s", live->cpu_s},
                      {"cpu_share", live->duration_s > 0 ? live->cpu_s / live->duration_s : 0.0},
                      {"scan_rate_hz", live->duration_s > 0 ? static_cast<double>(d.scans) / live->duration_s : 0.0},
                      {"driver",
                       {{"scans", d.scans},
                        {"scans_lost", d.scans_lost},
                        {"corrupt_frames", d.corrupt_frames},
                        {"faults", d.faults},
                        {"connects", d.connects},
                        {"stalls", d.stalls},
                        {"resets", d.resets},
                        {"bytes_received", d.bytes_received}}},
                      {"latency_s",
                       {{"samples", live->latency_samples},
                        {"mean", live->latency_mean_s},
                        {"p99", live->latency_p99_s},
                        {"max", live->latency_max_s}}},
                      {"saves", live->saves},
                      {"save_failures", live->save_failures},
                      {"pose_reopens", live->pose_reopens}};
  }
  return summary.dump(2) + "\n";
}

namespace {

std::string seconds_text(double s) {
  char text[48];
  std::snprintf(text, sizeof text, "%.3f", s);
  return text;
}

}  // namespace

std::string mapping_shortfall(const ScanMapperStats& s, const TimeRange& scans, const TimeRange& poses,
                              const std::string& clock) {
  if (s.scans == 0 || s.integrated * 2 >= s.scans) return {};
  std::string why = std::to_string(s.integrated) + " scans mapped of " + std::to_string(s.scans) + ": ";
  if (poses.count == 0) {
    why += "no usable pose arrived";
  } else {
    why += "the scans span " + seconds_text(scans.first_s) + " .. " + seconds_text(scans.last_s) + " s, the poses " +
           seconds_text(poses.first_s) + " .. " + seconds_text(poses.last_s) + " s (" + clock + " clock)";
    if (scans.count > 0 && (scans.last_s < poses.first_s || scans.first_s > poses.last_s)) {
      why += ": they do not overlap; are the poses on the other clock (--clock host|sensor)?";
    }
  }
  why += "; skipped: " + std::to_string(s.before_first_pose) + " before the first pose, " +
         std::to_string(s.after_last_pose) + " after the last (or waited too long), " + std::to_string(s.pose_gap) +
         " in gaps between poses wider than the maximum (--max-pose-gap-s), " + std::to_string(s.rejected) +
         " rejected (steps or length that do not fit the sensor)";
  return why;
}

std::size_t scans_mapped(const ScanMapper& mapper) {
  const MapperTotals& t = mapper.mapper().totals();
  const std::size_t rejected = t.scans_rejected_for_time + t.scans_rejected_for_pose;
  const std::size_t integrated = mapper.stats().integrated;
  return integrated > rejected ? integrated - rejected : 0;
}

std::string empty_run_failure(const ScanMapper& mapper, const ExportedMap& layers, const TimeRange& scans,
                              const MapRunChoices& choices) {
  const ScanMapperStats& s = mapper.stats();
  const MapperTotals& t = mapper.mapper().totals();
  if (s.integrated == 0) return {};
  const std::string n = std::to_string(s.integrated);
  if (scans_mapped(mapper) == 0) {
    if (t.scans_rejected_for_time == 0) {
      return "no scan was mapped: all " + n + " scans with poses had a pose that is not a number; check --poses";
    }
    std::string why = "no scan was mapped: " + std::to_string(t.scans_rejected_for_time) + " of the " + n +
                      " scans with poses were rejected as stale, their times not later than the last scan mapped";
    const bool older_than_map = !choices.resume_path.empty() && choices.resumed_last_scan_time_s && scans.count > 0 &&
                                scans.last_s <= *choices.resumed_last_scan_time_s;
    if (older_than_map) {
      why += ": the scans span " + seconds_text(scans.first_s) + " .. " + seconds_text(scans.last_s) +
             " s and the map of --resume " + choices.resume_path + " ends at " +
             seconds_text(*choices.resumed_last_scan_time_s) +
             " s, so they are older than the map; resume from a map made before these scans, or leave out --resume";
    } else {
      why += ": the scans' times go backwards or repeat (" + seconds_text(scans.first_s) + " .. " +
             seconds_text(scans.last_s) + " s); check their clock (--clock host|sensor)";
    }
    return why;
  }
  if (map_coverage(layers) > 0.0) return {};
  std::string why = "the map is empty (coverage 0 %) although " + std::to_string(scans_mapped(mapper)) +
                    " scans were mapped: " + std::to_string(t.outside_map) + " of their beams fell outside the window";
  if (t.integrated > 0) why += " and the " + std::to_string(t.integrated) + " in it were left behind as it moved";
  if (!choices.window.empty() && choices.window != "fit") {
    why += "; --window " + choices.window + " holds none of the points: centre it on them";
    if (choices.window_fit_possible) why += ", or use --window fit";
  } else if (choices.config_path.empty()) {
    const SensorMount& mount = mapper.options().config.mount;
    char text[160];
    std::snprintf(text, sizeof text, "the default mount (%.2f m high, pitched %.0f deg down)", mount.height_m,
                  mount.pitch_rad * 180.0 / 3.14159265358979323846);
    why += "; no --config was given, so the points were placed by " + std::string(text) +
           ": give the sensor's mount with --config (docs/config.md)";
  } else {
    why += "; check the mount in --config " + choices.config_path + " (height, pitch, offsets)";
  }
  if (choices.window.empty() && choices.window_fit_possible) why += ", or see the whole run with --window fit";
  return why;
}

ExportedMap filtered_map_layers(const ScanMapper& mapper, MapFilter filter) {
  switch (filter) {
    case MapFilter::fill: return mapper.filled_layers();
    case MapFilter::none: return export_map(mapper.map());
    case MapFilter::cas: {
      ElevationMap copy = mapper.map();
      CasOptions cas;
      cas.fill = mapper.options().config.fill;
      CasFilter(cas).apply(copy);
      return export_map(copy);
    }
  }
  return mapper.filled_layers();
}

ExportedMap write_map_outputs(const ScanMapper& mapper, const scip::ScipParameters& sensor, const MapRunInfo& info,
                                const LiveRunStats* live, const std::string& directory) {
  ExportedMap layers = filtered_map_layers(mapper, info.map_filter);
  io::MapOutputOptions style;
  style.elevation_title = "Elevation";  // the same for live and replay: their pictures must be equal
  style.certainty_max = mapper.options().config.mapper.update.certainty_max;
  if (info.elevation_range_m) {
    style.elevation_min_m = info.elevation_range_m->first;
    style.elevation_max_m = info.elevation_range_m->second;
  }
  io::OutputFolder staged(directory, info.out_option, info.other_files);
  io::write_map_layers(layers, staged.path(), style);
  io::write_text_file(staged.file("summary.json"), map_summary_json(mapper, layers, sensor, info, live), "summary");
  // The mapper's own state (before the fill-in), from which mapping can resume.
  io::MapFileMetadata metadata = io::map_file_metadata(mapper.options().config, info.command + " " + info.scans_from);
  metadata.last_scan_time_s = mapper.mapper().last_scan_time_s();
  metadata.last_pose = mapper.mapper().last_pose();
  io::save_map_file(staged.file("map.smap"), mapper.map(), metadata);
  if (info.extra_outputs) info.extra_outputs(staged.path());
  staged.commit();
  return layers;
}

}  // namespace stridemap
