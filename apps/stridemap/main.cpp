// stridemap command-line tool: terrain maps from active 2D range sensors.
//
// Exit codes (README.md, docs/reliability.md): 0 done (also --help,
// --version and a bare `stridemap`, which prints the help); 2 bad input or
// usage, always as one `stridemap: error:` line; 1 a run that failed its own
// checks (soak); 3 a bug (an exception that is not an input error).
#include <cstdio>
#include <exception>
#include <string>

#include "commands.hpp"
#include "output_guard.hpp"
#include "terminal_output.hpp"
#include "stridemap/core/error.hpp"
#include "stridemap/core/printable_text.hpp"

namespace {

constexpr int kExitBadInput = 2;
constexpr int kExitBug = 3;

void print_error(const std::string& prefix, const std::string& message) {
  std::fflush(stdout);
  std::fprintf(stderr, "stridemap: %s: %s\n", prefix.c_str(), stridemap::printable_text(message).c_str());
}

// "stridemap experiment cart-rail": the deepest sub-command the parser
// reached, so that the hint points at the help that lists the option.
std::string command_path(const CLI::App& app) {
  std::string path = app.get_name();
  const CLI::App* at = &app;
  for (;;) {
    const std::vector<const CLI::App*> chosen = at->get_subcommands([](const CLI::App* sub) { return sub->parsed(); });
    if (chosen.empty()) return path;
    at = chosen.front();
    path += " " + at->get_name();
  }
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"stridemap: terrain maps for walking robots from active 2D range sensors", "stridemap"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "stridemap 0.1.0");
  stridemap::cli::add_verbosity_flags(app);  // before the sub-commands: they inherit the fallthrough
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
  stridemap::cli::register_map(app);
  stridemap::cli::register_soak(app);
  stridemap::cli::register_import(app);
  stridemap::cli::register_map_file_commands(app);
  stridemap::cli::register_report(app);
  stridemap::cli::register_random_scenes(app);  // after register_experiment
  stridemap::cli::register_foothold_experiment(app);
  stridemap::cli::register_moved_objects_experiment(app);
  if (argc <= 1) {
    // Nothing asked: show what can be asked, as --help does.
    std::fputs(app.help().c_str(), stdout);
    return 0;
  }
  stridemap::cli::install_cleanup_signals();
  try {
    app.parse(argc, argv);
  } catch (const CLI::Success& e) {
    return app.exit(e);  // --help, --help-all, --version: CLI11 prints them, exit 0
  } catch (const CLI::ParseError& e) {
    // CLI11's own codes (104-109...) would tell a script nothing the docs promise.
    print_error("error", std::string(e.what()) + " (see '" + command_path(app) + " --help')");
    return kExitBadInput;
  } catch (const stridemap::cli::RunFailed& e) {
    print_error("error", e.what());
    return 1;
  } catch (const stridemap::InputError& e) {
    print_error("error", e.what());
    return kExitBadInput;
  } catch (const std::exception& e) {
    print_error("internal error", e.what());
    return kExitBug;
  }
  return 0;
}
