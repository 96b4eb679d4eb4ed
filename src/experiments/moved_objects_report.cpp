// The moved-objects experiment's files: summary.json, table.txt and
// standing.png (cells still standing after each object left, scan by scan,
// with the clean-up off and on).
#include <filesystem>

#include <nlohmann/json.hpp>

#include "stridemap/experiments/moved_objects.hpp"
#include "stridemap/io/text_file.hpp"
#include "stridemap/mapfile/map_file.hpp"
#include "stridemap/render/line_plot.hpp"
#include "stridemap/render/png_image.hpp"

namespace stridemap {
namespace {

nlohmann::json run_json(const MovedObjectsRun& run) {
  nlohmann::json objects = nlohmann::json::array();
  for (const MovedObjectTrack& t : run.objects) {
    objects.push_back({{"name", t.name},
                       {"left_at_s", t.left_at_s},
                       {"left_at_scan", t.left_at_scan},
                       {"standing_when_left", t.standing_when_left},
                       {"standing_after_each_scan", t.standing},
                       {"scans_until_half_cleared",
                        t.scans_until_half_cleared ? nlohmann::json(*t.scans_until_half_cleared) : nlohmann::json()},
                       {"scans_until_cleared", t.scans_until_cleared ? nlohmann::json(*t.scans_until_cleared) : nlohmann::json()}});
  }
  return {{"visibility", run.visibility},
          {"objects", objects},
          {"cells_contradicted", run.cells_contradicted},
          {"cells_cleared", run.cells_cleared},
          {"cells_wrongly_cleared", run.cells_wrongly_cleared}};
}

}  // namespace

void write_moved_objects_outputs(const MovedObjectsResult& result, const MovedObjectsOptions& options,
                                 const std::string& scene_path, const std::string& directory) {
  const std::filesystem::path dir(directory);
  const nlohmann::json summary = {{"experiment", "moved-objects"},
                                  {"tool_version", io::tool_version()},
                                  {"source", "simulation"},
                                  {"scene", scene_path},
                                  {"seed", options.seed},
                                  {"scans", result.scans},
                                  {"standing_above_m", options.standing_above_m},
                                  {"visibility_options",
                                   {{"uncertainty_factor", options.visibility.uncertainty_factor},
                                    {"relief_factor", options.visibility.relief_factor},
                                    {"certainty_decrement", options.visibility.certainty_decrement},
                                    {"beam_spacing_cells", options.visibility.beam_spacing_cells}}},
                                  {"off", run_json(result.off)},
                                  {"on", run_json(result.on)}};
  io::write_text_file((dir / "summary.json").string(), summary.dump(2) + "\n", "summary");
  io::write_text_file((dir / "table.txt").string(), moved_objects_table(result), "table");

  static constexpr std::array<std::array<std::uint8_t, 3>, 4> kColours{{{0, 90, 180}, {200, 80, 0}, {0, 140, 60}, {140, 0, 140}}};
  std::vector<io::PlotSeries> series;
  for (const MovedObjectsRun* run : {&result.off, &result.on}) {
    for (std::size_t b = 0; b < run->objects.size(); ++b) {
      const MovedObjectTrack& t = run->objects[b];
      io::PlotSeries s;
      s.label = t.name + (run->visibility ? ", clean-up on" : ", off");
      s.colour = kColours[(2 * b + (run->visibility ? 1 : 0)) % kColours.size()];
      s.x.push_back(0.0);
      s.y.push_back(static_cast<double>(t.standing_when_left));
      for (std::size_t k = 0; k < t.standing.size(); ++k) {
        s.x.push_back(static_cast<double>(k + 1));
        s.y.push_back(static_cast<double>(t.standing[k]));
      }
      series.push_back(std::move(s));
    }
  }
  io::LinePlotOptions plot;
  plot.title = "Cells still standing after the object left (simulated URG-04LX, seed " + std::to_string(options.seed) + ")";
  plot.x_label = "scans since it left";
  plot.y_label = "footprint cells above the truth";
  plot.y_min = 0.0;
  io::write_png((dir / "standing.png").string(), io::render_line_plot(series, plot));
}

}  // namespace stridemap
