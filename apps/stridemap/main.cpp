// stridemap command-line tool: terrain maps from active 2D range sensors.
#include <cstdio>
#include <exception>

#include "commands.hpp"
#include "stridemap/core/error.hpp"

int main(int argc, char** argv) {
  CLI::App app{"stridemap: terrain maps for walking robots from active 2D range sensors"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "stridemap 0.1.0");
  stridemap::cli::register_calibrate_range(app);
  stridemap::cli::register_calibrate_structured_light(app);
  stridemap::cli::register_detect_stripe(app);
  stridemap::cli::register_experiment(app);
  stridemap::cli::register_walk_experiments(app);
  stridemap::cli::register_sensor_report(app);
  stridemap::cli::register_simulate_stripe_image(app);
  stridemap::cli::register_emulate_urg(app);
  stridemap::cli::register_record(app);
  stridemap::cli::register_live(app);
  stridemap::cli::register_soak(app);
  stridemap::cli::register_import(app);
  stridemap::cli::register_map_file_commands(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  } catch (const stridemap::InputError& e) {
    std::fprintf(stderr, "stridemap: error: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "stridemap: internal error: %s\n", e.what());
    return 3;
  }
  return 0;
}
