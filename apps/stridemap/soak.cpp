// `stridemap soak`: the long run of docs/reliability.md. Drives the
// simulated robot round a circuit far larger than the map for many scans,
// with bad scans injected, and fails (exit 1) on a lost scan, an invalid
// cell, growing memory or, with --repeat 2, maps that differ between two
// runs with the same seed. `make soak` runs the full 100,000 scans.
#include <cinttypes>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <system_error>

#include "cli_parsing.hpp"
#include "commands.hpp"
#include "installed_data.hpp"
#include "terminal_output.hpp"
#include "output_guard.hpp"
#include "stridemap/core/printable_text.hpp"
#include "stridemap/config/scene_yaml.hpp"
#include "stridemap/core/error.hpp"
#include "stridemap/experiments/soak.hpp"
#include "stridemap/experiments/walk_soak_motion.hpp"
#include "stridemap/io/text_file.hpp"

namespace stridemap::cli {
namespace {

struct SoakCommandOptions {
  bool overwrite = false;
  static constexpr const char* kDefaultScene = "scenes/soak_circuit.yaml";
  std::string scene_path = kDefaultScene;
  std::string out_dir;  ///< empty: no summary file
  std::uint64_t scans = 100000;
  std::uint64_t seed = 1;
  int repeat = 1;
  double radius_m = 3.0;
  std::string motion = "circuit";
  bool planner_thread = true;
  std::string global_map;  ///< empty: no global map
  int tile_cells = GlobalMapOptions{}.tile_cells;
};

std::string hex(std::uint64_t value) {
  char text[20];
  std::snprintf(text, sizeof text, "%016" PRIx64, value);
  return text;
}

void print_run(const SoakResult& r, const SoakOptions& options) {
  const MapperTotals& t = r.totals;
  const double map_side_m = options.mapper.grid.cells_per_side * options.mapper.grid.cell_size_m;
  std::printf("Soak run (simulated URG-04LX): %" PRIu64 " scans, %s\n", r.scans_simulated, r.motion.c_str());
  std::printf("  path %.1f m long over %.2f x %.2f m; the map is %.2f x %.2f m and followed the robot "
              "(%" PRIu64 " cells reset by moves)\n",
              r.path_length_m, r.path_extent_x_m, r.path_extent_y_m, map_side_m, map_side_m, r.cells_reset_by_moves);
  std::printf("  scans to the mapper %" PRIu64 ": %zu rejected for their pose (%" PRIu64 " NaN poses injected), "
              "%zu for their time (%" PRIu64 " duplicates + %" PRIu64 " out of order injected)\n",
              r.scans_to_mapper, t.scans_rejected_for_pose, r.injected_nan_poses, t.scans_rejected_for_time,
              r.injected_duplicates, r.injected_out_of_order);
  std::printf("  beams %zu: integrated %zu, invalid range %zu, invalid beam %zu, outside the map %zu, "
              "in rejected scans %" PRIu64 "\n",
              t.beams, t.integrated, t.invalid_range, t.invalid_beam, t.outside_map, r.beams_of_rejected_scans);
  std::printf("  integrity checks %" PRIu64 ": %" PRIu64 " invalid cells; planner thread checked %" PRIu64
              " snapshots: %" PRIu64 " invalid cells; %" PRIu64 " published, %" PRIu64 " skipped\n",
              r.integrity_checks, r.invalid_cells, r.reader_snapshots, r.reader_invalid_cells, r.published,
              r.publishes_skipped);
  if (!r.checkpoints.empty()) {
    const SoakCheckpoint& a = r.checkpoints.front();
    const SoakCheckpoint& b = r.checkpoints.back();
    std::printf("  memory: heap in use %zu B at scan %" PRIu64 ", %zu B at scan %" PRIu64
                "; resident %.1f MiB -> %.1f MiB\n",
                a.heap_in_use_bytes, a.scan, b.heap_in_use_bytes, b.scan, static_cast<double>(a.resident_bytes) / 1048576.0,
                static_cast<double>(b.resident_bytes) / 1048576.0);
  }
  if (r.global_map.enabled) {
    const SoakGlobalMap& g = r.global_map;
    std::printf("  global map: %zu tiles on disk (%.1f MiB), %zu written, %zu read back, %zu cells restored; "
                "%" PRIu64 " measured cells on disk, %" PRIu64 " measured first by the mapper, %" PRIu64
                " invalid\n",
                g.tiles_on_disk, static_cast<double>(g.bytes_on_disk) / 1048576.0, g.tiles_written, g.tiles_read,
                g.cells_restored, g.measured_on_disk, g.first_measured, g.invalid_on_disk);
  }
  std::printf("  run hash %s (over %zu checkpoints), %.1f s\n", hex(r.run_hash).c_str(), r.checkpoints.size(),
              r.wall_time_s);
}

nlohmann::json to_json(const SoakResult& r) {
  nlohmann::json checkpoints = nlohmann::json::array();
  for (const SoakCheckpoint& c : r.checkpoints) {
    checkpoints.push_back({{"scan", c.scan},
                           {"map_hash", hex(c.map_hash)},
                           {"snapshot_hash", hex(c.snapshot_hash)},
                           {"measured_cells", c.measured_cells},
                           {"heap_in_use_bytes", c.heap_in_use_bytes},
                           {"resident_bytes", c.resident_bytes},
                           {"global_map_tiles", c.global_map_tiles}});
  }
  const MapperTotals& t = r.totals;
  return {{"simulated", true},
          {"motion", r.motion},
          {"scans_simulated", r.scans_simulated},
          {"scans_to_mapper", r.scans_to_mapper},
          {"scans_rejected_for_pose", t.scans_rejected_for_pose},
          {"scans_rejected_for_time", t.scans_rejected_for_time},
          {"injected", {{"nan_poses", r.injected_nan_poses},
                        {"duplicates", r.injected_duplicates},
                        {"out_of_order", r.injected_out_of_order}}},
          {"beams", t.beams},
          {"integrated", t.integrated},
          {"invalid_range", t.invalid_range},
          {"invalid_beam", t.invalid_beam},
          {"outside_map", t.outside_map},
          {"integrity_checks", r.integrity_checks},
          {"invalid_cells", r.invalid_cells},
          {"planner_snapshots", r.reader_snapshots},
          {"planner_invalid_cells", r.reader_invalid_cells},
          {"path_length_m", r.path_length_m},
          {"path_extent_m", {r.path_extent_x_m, r.path_extent_y_m}},
          {"global_map", r.global_map.enabled ? nlohmann::json{{"tiles_on_disk", r.global_map.tiles_on_disk},
                                                                {"bytes_on_disk", r.global_map.bytes_on_disk},
                                                                {"tiles_written", r.global_map.tiles_written},
                                                                {"tiles_read", r.global_map.tiles_read},
                                                                {"cells_restored", r.global_map.cells_restored},
                                                                {"measured_on_disk", r.global_map.measured_on_disk},
                                                                {"first_measured", r.global_map.first_measured},
                                                                {"invalid_on_disk", r.global_map.invalid_on_disk}}
                                              : nlohmann::json(nullptr)},
          {"run_hash", hex(r.run_hash)},
          {"wall_time_s", r.wall_time_s},
          {"failures", r.failures()},
          {"checkpoints", checkpoints}};
}

void run(const SoakCommandOptions& o) {
  if (o.motion != "circuit" && o.motion != "walk") {
    throw InputError("--motion: expected circuit or walk, got '" + o.motion + "'");
  }
  const Scene scene = load_scene_yaml(o.scene_path);
  if (!o.out_dir.empty()) {
    const std::string dir = (std::filesystem::path(o.out_dir) / "soak").string();
    refuse_output_that_is_an_input("--out", dir, {{"--scene", o.scene_path}});
    io::check_output_folder(dir, "--out", other_files(o.overwrite));
  }
  if (!o.global_map.empty()) {
    std::error_code ec;
    if (std::filesystem::exists(o.global_map, ec) &&
        !(std::filesystem::is_directory(o.global_map, ec) && std::filesystem::is_empty(o.global_map, ec))) {
      throw InputError("--global-map: '" + o.global_map +
                       "' exists and is not an empty folder; the tiles go only into a new or empty one");
    }
  }
  std::unique_ptr<SoakMotion> moving;
  if (o.motion == "walk") {
    WalkSoakOptions walk;
    walk.seed = o.seed;
    moving = std::make_unique<WalkSoakMotion>(scene, walk);
  } else {
    CircuitOptions circuit;
    circuit.radius_m = o.radius_m;
    circuit.seed = o.seed;
    moving = std::make_unique<CircuitMotion>(scene, circuit);
  }
  const SoakMotion& motion = *moving;
  SoakOptions options;
  options.scans = o.scans;
  options.seed = o.seed;
  options.reader_thread = o.planner_thread;

  std::vector<std::string> failures;
  nlohmann::json runs = nlohmann::json::array();
  std::uint64_t first_hash = 0;
  io::ProgressBar bar = progress_bar("soak", "scans");
  int run_index = 0;
  if (bar.enabled()) {
    options.progress = [&](std::size_t done, std::size_t total) {
      bar.update(static_cast<std::size_t>(run_index) * total + done, static_cast<std::size_t>(o.repeat) * total);
    };
  }
  for (int k = 0; k < o.repeat; ++k) {
    run_index = k;
    // Each run its own folder: a store writes only into a new or empty one.
    if (!o.global_map.empty()) {
      options.global_map.folder = (std::filesystem::path(o.global_map) / ("run" + std::to_string(k + 1))).string();
      options.global_map.tile_cells = o.tile_cells;
    }
    const SoakResult result = run_soak(scene, motion, options);
    bar.clear();
    print_run(result, options);
    for (const std::string& f : result.failures()) failures.push_back("run " + std::to_string(k + 1) + ": " + f);
    if (k == 0) first_hash = result.run_hash;
    if (k > 0 && result.run_hash != first_hash) {
      failures.push_back("run " + std::to_string(k + 1) + " gave run hash " + hex(result.run_hash) + ", run 1 " +
                         hex(first_hash) + ": the same seed must give the same maps");
    }
    runs.push_back(to_json(result));
  }
  if (o.repeat > 1 && failures.empty()) std::printf("%d runs with seed %" PRIu64 ": bit-identical maps\n", o.repeat, o.seed);
  if (!o.out_dir.empty()) {
    const std::filesystem::path dir = std::filesystem::path(o.out_dir) / "soak";
    const nlohmann::json summary = {{"scene", o.scene_path}, {"seed", o.seed}, {"runs", runs}, {"failures", failures}};
    write_output_set(dir.string(), "--out", [&](const std::string& folder) {
      io::write_text_file(folder + "/summary.json", summary.dump(2) + "\n", "summary");
    }, other_files(o.overwrite));
    std::printf("wrote %s\n", printable_text((dir / "summary.json").string()).c_str());
  }
  if (!failures.empty()) {
    for (const std::string& f : failures) std::fprintf(stderr, "stridemap: soak failed: %s\n", f.c_str());
    std::fflush(stdout);
    std::exit(1);
  }
  std::printf("soak passed\n");
}

}  // namespace

void register_soak(CLI::App& app) {
  auto options = std::make_shared<SoakCommandOptions>();
  CLI::App* command = app.add_subcommand(
      "soak", "Long simulated run: every scan accounted for, no invalid cell, flat memory, same seed same maps");
  command->add_option("--scene", options->scene_path, "Scene file")->capture_default_str();
  command->add_option("--scans", options->scans, "Scans to simulate")->capture_default_str()->check(whole_from_to(1, 100000000));
  command->add_option("--seed", options->seed, "Seed of the simulator and the pose errors")->capture_default_str()
      ->check(seed_value());
  command->add_option("--repeat", options->repeat, "Runs with the same seed, compared bit for bit")
      ->capture_default_str()
      ->check(whole_from_to(1, 10));
  command->add_option("--motion", options->motion,
                      "circuit (a circle driven round and round) or walk (the walking robot's gait round the "
                      "scene's walk_path, a closed loop)")
      ->capture_default_str();
  command->add_option("--radius-m", options->radius_m, "Radius of the circuit [m]")->capture_default_str()
      ->check(number_from_to(0.05, 1000.0, "m"));
  command->add_option("--out", options->out_dir, "Folder for soak/summary.json");
  add_output_folder_overwrite_flag(*command, options->overwrite);
  command->add_option("--global-map", options->global_map,
                      "Keep a tiled global map in this new or empty folder (run1/, run2/ per --repeat) and check "
                      "it at the end (docs/global_map.md)");
  command->add_option("--tile-cells", options->tile_cells, "Cells per side of a global map tile")
      ->capture_default_str()
      ->check(whole_from_to(1, 4096));
  command->add_flag("!--no-planner-thread", options->planner_thread, "Do not read snapshots from a second thread");
  command->callback([options] {
    options->scene_path = resolve_default_data_file("--scene", options->scene_path, SoakCommandOptions::kDefaultScene);
    run(*options);
  });
}

}  // namespace stridemap::cli
