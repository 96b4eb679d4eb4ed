#include "stridemap/experiments/mixed_pixels.hpp"

#include <cstdio>
#include <filesystem>
#include <system_error>

#include <nlohmann/json.hpp>

#include "stridemap/core/error.hpp"
#include "stridemap/experiments/cart_rail_report.hpp"
#include "stridemap/io/text_file.hpp"
#include "stridemap/mapfile/map_file.hpp"
#include "stridemap/preprocess/scan_filter_registry.hpp"
#include "stridemap/render/grid_render.hpp"
#include "stridemap/render/png_image.hpp"

namespace stridemap {

std::vector<MixedPixelsCase> default_mixed_pixels_cases() {
  using K = ScanFilterKind;
  std::vector<MixedPixelsCase> cases{
      {"no mixed pixels (reference)", false, {}, MapFilter::fill},
      {"ideal (drops the labelled beams)", true, {}, MapFilter::fill, true},
      {"none", true, {}, MapFilter::fill},
      {"range-clustering", true, {K::range_clustering}, MapFilter::fill},
      {"scan-sequence", true, {K::scan_sequence}, MapFilter::fill},
      {"paper (range-clustering + scan-sequence)", true, {K::range_clustering, K::scan_sequence}, MapFilter::fill},
      {"shadow (baseline)", true, {K::shadow}, MapFilter::fill},
      {"speckle (baseline)", true, {K::speckle}, MapFilter::fill},
  };
  // A filter registered beyond the built-in ones is compared too, with no
  // change here (docs/architecture.md, "Adding a scan filter").
  const std::size_t filters = registered_scan_filters().size();
  for (std::size_t kind = static_cast<std::size_t>(K::between_scans) + 1; kind < filters; ++kind) {
    const auto k = static_cast<K>(kind);
    cases.push_back({std::string(scan_filter_name(k)), true, {k}, MapFilter::fill});
  }
  cases.push_back({"CAS on the map", true, {}, MapFilter::cas});
  return cases;
}

MixedPixelsResult run_mixed_pixels(const Scene& scene, const CartRailOptions& base,
                                   const std::vector<MixedPixelsCase>& cases) {
  // Every case uses these options: reject bad ones before the first run.
  base.footprint.validate();
  (void)ScanFilterChain({}, base.filter_options);  // checks every built-in filter's options
  MixedPixelsResult result;
  for (const MixedPixelsCase& c : cases) {
    CartRailOptions options = base;
    options.progress = progress_of_part(base.progress, result.rows.size(), cases.size());
    options.mixed_pixels = c.mixed_pixels;
    // The reference case is the sensor without mixed measurements of any
    // kind: no footprint and no lagging gain control either.
    if (!c.mixed_pixels) options.sim.receiver.enabled = false;
    options.filters = c.filters;
    options.map_filter = c.map_filter;
    options.drop_labelled_mixed = c.drop_labelled_mixed;
    CartRailResult run = run_cart_rail(scene, options);
    result.rows.push_back({c, run.beams, run.score, run.cas_removed_cells});
    const bool paper = c.mixed_pixels && c.filters.size() == 2 && c.map_filter == MapFilter::fill;
    if (c.drop_labelled_mixed) continue;
    if (c.mixed_pixels && c.filters.empty() && c.map_filter == MapFilter::fill) result.unfiltered = std::move(run);
    else if (paper) result.paper = std::move(run);
    else if (c.mixed_pixels && c.map_filter == MapFilter::cas) result.cas = std::move(run);
  }
  return result;
}

namespace {

const MixedPixelsRow* find_row(const MixedPixelsResult& r, const std::string& name) {
  for (const MixedPixelsRow& row : r.rows)
    if (row.config.name == name) return &row;
  return nullptr;
}

double reduction_pct(std::size_t before, std::size_t after) {
  return before ? 100.0 * (static_cast<double>(before) - static_cast<double>(after)) / static_cast<double>(before) : 0.0;
}

}  // namespace

double mixed_artifact_reduction(const MixedPixelsResult& r, const MixedPixelsRow& row) {
  const MixedPixelsRow* none = find_row(r, "none");
  const MixedPixelsRow* ideal = nullptr;
  for (const MixedPixelsRow& candidate : r.rows)
    if (candidate.config.drop_labelled_mixed) ideal = &candidate;
  if (!none || !ideal || none->score.artifact_cells <= ideal->score.artifact_cells) return 0.0;
  const double removable =
      static_cast<double>(none->score.artifact_cells) - static_cast<double>(ideal->score.artifact_cells);
  return (static_cast<double>(none->score.artifact_cells) - static_cast<double>(row.score.artifact_cells)) / removable;
}

std::string mixed_pixels_table(const MixedPixelsResult& r) {
  const MixedPixelsRow* none = find_row(r, "none");
  std::string out = "mixed pixels, cart rail (simulated)\n";
  out += "case                                      mixed  recall  clean drop   F1    artifacts  reduction  of mixed  RMS [mm]\n";
  char line[256];
  for (const MixedPixelsRow& row : r.rows) {
    const bool has_mixed = row.config.mixed_pixels;
    std::snprintf(line, sizeof line, "%-40s %6zu  %5.1f%%   %6.2f%%   %5.3f  %9zu  %8.1f%%  %7.1f%%  %7.1f\n",
                  row.config.name.c_str(), row.beams.mixed, has_mixed ? 100.0 * row.beams.mixed_recall() : 0.0,
                  100.0 * row.beams.clean_drop_rate(), row.beams.f1(), row.score.artifact_cells,
                  none ? reduction_pct(none->score.artifact_cells, row.score.artifact_cells) : 0.0,
                  has_mixed ? 100.0 * mixed_artifact_reduction(r, row) : 0.0, row.score.rms_error_m * 1000);
    out += line;
  }
  return out;
}

std::string mixed_pixels_summary_json(const MixedPixelsResult& r, const CartRailOptions& base,
                                      const std::string& scene_path) {
  const MixedPixelsRow* none = find_row(r, "none");
  nlohmann::json rows = nlohmann::json::array();
  for (const MixedPixelsRow& row : r.rows) {
    rows.push_back({{"case", row.config.name},
                    {"mixed_pixels", row.config.mixed_pixels},
                    {"filters", scan_filter_list_name(row.config.filters)},
                    {"map_filter", std::string(map_filter_name(row.config.map_filter))},
                    {"drops_labelled_mixed", row.config.drop_labelled_mixed},
                    {"beams",
                     {{"clean", row.beams.clean},
                      {"mixed", row.beams.mixed},
                      {"dropped", row.beams.dropped},
                      {"clean_removed", row.beams.clean_removed},
                      {"mixed_removed", row.beams.mixed_removed},
                      {"mixed_recall", row.beams.mixed_recall()},
                      {"clean_drop_rate", row.beams.clean_drop_rate()},
                      {"precision", row.beams.precision()},
                      {"f1", row.beams.f1()}}},
                    {"map",
                     {{"artifact_cells", row.score.artifact_cells},
                      {"artifact_reduction_pct",
                       none ? reduction_pct(none->score.artifact_cells, row.score.artifact_cells) : 0.0},
                      {"mixed_artifact_reduction_pct",
                       row.config.mixed_pixels ? 100.0 * mixed_artifact_reduction(r, row) : 0.0},
                      {"rms_error_m", row.score.rms_error_m},
                      {"max_error_m", row.score.max_error_m},
                      {"coverage", row.score.coverage},
                      {"cas_removed_cells", row.cas_removed_cells}}}});
  }
  const nlohmann::json summary = {{"experiment", "mixed-pixels"},
                                 {"tool_version", io::tool_version()},
                                  {"sensor", "urg"},
                                  {"source", "simulation"},
                                  {"seed", base.seed},
                                  {"scene", scene_path},
                                  {"artifact_threshold_m", base.score.artifact_threshold_m},
                                  {"cases", rows}};
  return summary.dump(2) + "\n";
}

void write_mixed_pixels_outputs(const MixedPixelsResult& r, const CartRailOptions& base, const std::string& scene_path,
                                const std::string& directory) {
  const std::filesystem::path dir(directory);
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) throw InputError(dir.string() + ": cannot create the output folder: " + ec.message());
  const auto picture = [&](const CartRailResult& run, const std::string& file, const std::string& title) {
    const MapSnapshot& s = run.snapshot;
    if (s.elevation_m().size() == 0) return;
    io::GridRenderOptions style;
    style.title = title;
    style.units = "m";
    style.cell_size_m = s.cell_size_m;
    style.min_value = std::min(0.0f, s.truth_m.minCoeff());
    style.max_value = std::max(s.truth_m.maxCoeff(), 0.01f);
    io::write_png((dir / file).string(), io::render_grid(s.elevation_m(), style).image);
  };
  picture(r.unfiltered, "elevation_unfiltered.png", "Mixed pixels, no filtering (simulated)");
  picture(r.paper, "elevation_paper_filters.png", "Range clustering + scan sequence (simulated)");
  picture(r.cas, "elevation_cas.png", "CAS filter on the map (simulated)");
  io::write_text_file((dir / "summary.json").string(), mixed_pixels_summary_json(r, base, scene_path), "summary");
  // The printed table, for the report page to show as it is.
  io::write_text_file((dir / "table.txt").string(), mixed_pixels_table(r), "table");
}

}  // namespace stridemap
