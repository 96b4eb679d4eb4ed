#include "mapping_options.hpp"

#include <functional>
#include <memory>
#include <optional>

#include "cli_parsing.hpp"
#include "commands.hpp"
#include "report_command.hpp"
#include "terminal_output.hpp"
#include "window_placement.hpp"
#include "stridemap/core/error.hpp"
#include "stridemap/mapfile/map_file.hpp"
#include "stridemap/mapfile/map_resume_check.hpp"
#include "stridemap/mapfile/tile_store.hpp"
#include "stridemap/live/map_window.hpp"
#include "stridemap/preprocess/scan_filter_registry.hpp"

namespace stridemap::cli {
namespace {

// At parsing, so that a typo costs no run.
template <typename Parse>
std::function<std::string(const std::string&)> parsed_by(Parse parse) {
  return [parse](const std::string& text) {
    try {
      parse(text);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
}

// A run whose global map is not all on disk failed, whatever else it did.
void check_tiles_saved(const ScanMapper& mapper) {
  const io::TileStore* tiles = mapper.tile_store();
  if (!tiles) return;
  const io::TileStoreStats& s = tiles->stats();
  note("global map: " + std::to_string(tiles->tiles_on_disk().size()) + " tiles in " + tiles->folder() +
       (s.tiles_set_aside ? "; " + std::to_string(s.tiles_set_aside) + " damaged or missing, set aside and mapped anew"
                          : std::string()));
  if (tiles->failing()) {
    throw RunFailed("global map: " + std::to_string(tiles->unsaved()) + " changed tiles (or the manifest) could not be "
                    "written to " + tiles->folder() + " after " + std::to_string(s.write_failures) +
                    " tries (the warnings above say why); the map in --out holds the window only");
  }
}

}  // namespace

void add_mapping_options(CLI::App& command, MappingArgs& args) {
  command.add_option("--out", args.out_dir, "Output folder: elevation/certainty PNG and CSV, state.csv, summary.json")
      ->required();
  add_report_flag(command, args.report);
  command.add_option("--range", args.range,
                     "Colour range of elevation.png, MIN:MAX in metres (default: the 2nd to 98th percentile)")
      ->check(parsed_by([](const std::string& text) { parse_elevation_range(text); }));
  command.add_option("--window", args.window,
                     "Where the map's window stays: X,Y (its centre in the map frame, metres, e.g. 1.5,-0.2) or "
                     "fit (map: over everything the log measures, growing the map if needed). Default: it follows "
                     "the robot (docs/cli.md)")
      ->check(parsed_by([](const std::string& text) { parse_window_choice(text); }));
  command.add_option("--config", args.config_path, "Mapper configuration (YAML, docs/config.md)");
  command.add_option("--filters", args.filters,
                     "Scan filters in order, comma separated: " + scan_filter_choices())
      ->capture_default_str();
  command.add_option("--clock", args.clock,
                     "Clock of the pose times: host (Unix time of each scan's step 0, estimated by the driver) or "
                     "sensor (the URG's millisecond clock, in seconds)")
      ->capture_default_str();
  command.add_option("--max-pose-gap-s", args.max_pose_gap_s,
                     "Do not interpolate between poses farther apart than this")
      ->capture_default_str()
      ->check(number_from_to(0.001, 1e9, "s"));
  command.add_option("--map-filter", args.map_filter,
                     "What runs on a copy of the map before it is saved: fill (eq. 11), cas or none")
      ->capture_default_str();
  command.add_option("--global-map", args.global_map,
                     "Keep the cells that leave the window in tiles in this new or empty folder, and reload them "
                     "when the robot comes back (docs/global_map.md); overrides the config's global_map.folder");
  command.add_option("--resume", args.resume_path,
                     "Go on mapping from this map file (a map.smap of an earlier run, made with the same --config); "
                     "the new map goes to --out, the file itself is never changed");
}

LiveClock parse_clock(const std::string& name) {
  if (name == "host") return LiveClock::host;
  if (name == "sensor") return LiveClock::sensor;
  throw InputError("--clock: '" + name + "' is not a clock; use host or sensor");
}

ScanMapperOptions mapper_options(const MappingArgs& args) {
  parse_clock(args.clock);
  parse_map_filter(args.map_filter);
  const WindowChoice window = parse_window_choice(args.window);
  if (window.mode != WindowChoice::Mode::follow && !args.resume_path.empty()) {
    throw InputError("--window: a resumed map keeps the window of its map file (--resume " + args.resume_path +
                     "); leave out --window");
  }
  ScanMapperOptions options;
  if (!args.config_path.empty()) options.config = load_mapper_config(args.config_path);
  if (!args.global_map.empty()) options.config.global_map.folder = args.global_map;
  const std::string& tiles = options.config.global_map.folder;
  if (!tiles.empty() && (io::path_within(tiles, args.out_dir) || io::path_within(args.out_dir, tiles))) {
    // Refused now, not when the outputs are written after the mapping.
    throw InputError("--global-map: '" + tiles + "' and the --out folder '" + args.out_dir +
                     "' lie one inside the other; give the tiles a folder of their own");
  }
  if (window.mode == WindowChoice::Mode::center) {
    fix_window(options, window_centred_at(options.config.mapper.grid, window.center_m));
  }
  options.filters = parse_scan_filter_list(args.filters);
  if (!args.resume_path.empty()) {
    options.resume = std::make_shared<const io::MapFile>(io::load_map_file(args.resume_path));
    options.resume_source = "--resume " + args.resume_path;
    io::check_map_resumable(*options.resume, options.config, options.resume_source);
  }
  return options;
}

MapRunInfo run_info(const MappingArgs& args, const std::string& command, const std::string& scans_from) {
  MapRunInfo info = map_run_info(command, scans_from, args);
  if (args.report) {
    info.extra_outputs = [target = args.out_dir](const std::string& folder) { write_run_report(folder, target); };
  }
  return info;
}

std::string rejected_text(const ScanMapper& mapper) {
  const MapperTotals& t = mapper.mapper().totals();
  return std::to_string(t.scans_rejected_for_time) + " rejected as stale, " +
         std::to_string(t.scans_rejected_for_pose) + " for a bad pose";
}

void check_finished_run(const ScanMapper& mapper, const ExportedMap& layers, const TimeRange& scans,
                        const TimeRange& poses, const MappingArgs& args, const MapRunChoices& choices) {
  check_tiles_saved(mapper);
  const std::string why = mapping_shortfall(mapper.stats(), scans, poses, args.clock);
  if (!why.empty()) throw RunFailed(why);
  const std::string nothing = empty_run_failure(mapper, layers, scans, choices);
  if (!nothing.empty()) throw RunFailed(nothing);
}

}  // namespace stridemap::cli
