#include "terminal_output.hpp"

#include <cstdio>

#include "stridemap/core/printable_text.hpp"

namespace stridemap::cli {
namespace {

Verbosity& mutable_verbosity() {
  static Verbosity level;
  return level;
}

}  // namespace

const Verbosity& verbosity() { return mutable_verbosity(); }

void add_verbosity_flags(CLI::App& app) {
  Verbosity& level = mutable_verbosity();
  CLI::Option* quiet = app.add_flag("-q,--quiet", level.quiet, "No progress bars or notes on stderr (errors and warnings still)");
  app.add_flag("-v,--verbose", level.verbose, "Also say on stderr what was read, done and written")->excludes(quiet);
  // Every sub-command registered after this passes options it does not
  // know to its parent, so `stridemap map ... --quiet` works as well.
  app.fallthrough();
}

io::ProgressBar progress_bar(std::string label, std::string unit) {
  return io::ProgressBar::for_stderr(std::move(label), std::move(unit), verbosity().quiet);
}

void note(const std::string& text) {
  if (!verbosity().verbose) return;
  std::fprintf(stderr, "stridemap: %s\n", printable_text(text).c_str());
}

void print_outputs_line(const std::string& folder) { std::printf("outputs: %s\n", printable_text(folder).c_str()); }

}  // namespace stridemap::cli
