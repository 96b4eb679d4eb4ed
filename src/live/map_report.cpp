#include "stridemap/live/map_report.hpp"

#include <filesystem>

#include <nlohmann/json.hpp>

#include "stridemap/core/grid_map.hpp"
#include "stridemap/io/map_file.hpp"
#include "stridemap/io/text_file.hpp"

namespace stridemap {

std::string map_summary_json(const ScanMapper& mapper, const io::MapLayers& layers,
                             const scip::ScipParameters& sensor, const MapRunInfo& info, const LiveRunStats* live) {
  using nlohmann::json;
  const ScanMapperStats& s = mapper.stats();
  const MapperTotals& t = mapper.mapper().totals();
  std::size_t measured = 0, filled = 0;
  for (Eigen::Index i = 0; i < layers.state.size(); ++i) {
    const auto state = static_cast<CellState>(layers.state.data()[i]);
    measured += state == CellState::measured;
    filled += state == CellState::filled;
  }
  json summary = {
      {"command", info.command},
      {"scans_from", info.scans_from},
      {"poses_from", info.poses_from},
      {"clock", info.clock},
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
       {{"coverage", io::map_coverage(layers)},
        {"measured_cells", measured},
        {"filled_cells", filled},
        {"cells_per_side", layers.state.rows()},
        {"cell_size_m", layers.cell_size_m},
        {"min_cell", {layers.min_cell.x, layers.min_cell.y}}}},
      {"filters", scan_filter_list_name(mapper.options().filters)}};
  if (!info.log_damage.empty()) summary["log_damage"] = info.log_damage;
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
                        {"max", live->latency_max_s}}}};
  }
  return summary.dump(2) + "\n";
}

io::MapLayers write_map_outputs(const ScanMapper& mapper, const scip::ScipParameters& sensor, const MapRunInfo& info,
                                const LiveRunStats* live, const std::string& directory) {
  io::MapLayers layers = mapper.filled_layers();
  io::MapOutputOptions style;
  style.elevation_title = "Elevation";  // the same for live and replay: their pictures must be equal
  style.certainty_max = mapper.options().config.mapper.update.certainty_max;
  io::write_map_layers(layers, directory, style);
  io::write_text_file((std::filesystem::path(directory) / "summary.json").string(),
                      map_summary_json(mapper, layers, sensor, info, live), "summary");
  // The mapper's own state (before the fill-in), from which mapping can resume.
  io::MapFileMetadata metadata = io::map_file_metadata(mapper.options().config, info.command + " " + info.scans_from);
  metadata.last_scan_time_s = mapper.mapper().last_scan_time_s();
  io::save_map_file((std::filesystem::path(directory) / "map.smap").string(), mapper.mapper().map(), metadata);
  return layers;
}

}  // namespace stridemap
