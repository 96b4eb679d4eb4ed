#pragma once
// What the tool says on stderr besides errors and warnings: progress bars
// (only on a terminal, apps/stridemap/progress_bar.hpp) and, with --verbose, notes on
// what it read, did and wrote. --quiet silences both; errors and warnings
// are always printed.
#include <string>

#include <CLI/CLI.hpp>

#include "progress_bar.hpp"

namespace stridemap::cli {

struct Verbosity {
  bool quiet = false;
  bool verbose = false;
};

/// The global --quiet / --verbose of this run.
const Verbosity& verbosity();
/// Adds --quiet and --verbose to the top-level command; sub-commands pass
/// them up (CLI11 fallthrough), so they may stand anywhere on the line.
void add_verbosity_flags(CLI::App& app);

/// A progress bar on stderr, drawn on a terminal unless --quiet.
io::ProgressBar progress_bar(std::string label, std::string unit);

/// With --verbose: "stridemap: <text>" on stderr.
void note(const std::string& text);

/// "outputs: <folder>" on stdout, the last line of an experiment; the
/// folder is the user's text, so it goes through printable_text.
void print_outputs_line(const std::string& folder);

}  // namespace stridemap::cli
