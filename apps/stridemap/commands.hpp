#pragma once
// Each sub-command lives in its own file and registers itself on the CLI11
// application here; main() only dispatches and turns errors into messages.
#include <CLI/CLI.hpp>

namespace stridemap::cli {

void register_calibrate_range(CLI::App& app);
void register_experiment(CLI::App& app);
void register_sensor_report(CLI::App& app);
void register_soak(CLI::App& app);

}  // namespace stridemap::cli
