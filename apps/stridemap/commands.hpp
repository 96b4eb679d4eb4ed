#pragma once
// Each sub-command lives in its own file and registers itself on the CLI11
// application here; main() only dispatches and turns errors into messages.
#include <stdexcept>

#include <CLI/CLI.hpp>

namespace stridemap::cli {

/// A run that completed but failed its own checks (e.g. mapped nothing):
/// main() prints "stridemap: error: ..." and exits 1.
class RunFailed : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

void register_calibrate_range(CLI::App& app);
void register_calibrate_structured_light(CLI::App& app);
void register_detect_stripe(CLI::App& app);
void register_experiment(CLI::App& app);
void register_sensor_report(CLI::App& app);
void register_simulate_stripe_image(CLI::App& app);
void register_emulate_urg(CLI::App& app);  // emulate_urg.cpp
void register_record(CLI::App& app);       // record.cpp
void register_live(CLI::App& app);         // live.cpp
void register_map(CLI::App& app);          // map_command.cpp, after register_live
void register_walk_experiments(CLI::App& app);  // after register_experiment
void register_soak(CLI::App& app);
void register_import(CLI::App& app);              // import.cpp
void register_map_file_commands(CLI::App& app);  // map_file_commands.cpp: export, map-info
void register_report(CLI::App& app);              // report_command.cpp
void register_random_scenes(CLI::App& app);       // random_scenes.cpp: scene random, experiment fidelity
void register_foothold_experiment(CLI::App& app);  // foothold_command.cpp, after register_experiment
void register_moved_objects_experiment(CLI::App& app);  // moved_objects_command.cpp, after register_experiment

}  // namespace stridemap::cli
