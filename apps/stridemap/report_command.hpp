#pragma once
// `stridemap report DIR` and the `--report` flag of experiment, map and live:
// the run's report page (mapfile/report_page.hpp), report.html in the folder.
#include <string>

#include <CLI/CLI.hpp>

namespace stridemap::cli {

/// The folder of the report page's web assets the build or install put
/// beside the executable. Throws InputError naming where it looked.
std::string report_assets_dir();

/// Writes `folder`/report.html for the outputs in `folder` (the staging
/// folder of the output set `target`, before its commit), printing the
/// page's warnings.
void write_run_report(const std::string& folder, const std::string& target);

/// `--report` on a command; the flag's help says where the page goes.
CLI::Option* add_report_flag(CLI::App& command, bool& report);

}  // namespace stridemap::cli
