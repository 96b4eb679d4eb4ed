#include "report_command.hpp"

#include <cstdio>
#include <filesystem>
#include <memory>
#include <system_error>

#include "commands.hpp"
#include "installed_data.hpp"
#include "terminal_output.hpp"
#include "stridemap/core/error.hpp"
#include "stridemap/core/printable_text.hpp"
#include "stridemap/mapfile/report_page.hpp"

namespace stridemap::cli {
namespace {

struct ReportArgs {
  std::string directory;
  std::string out_path;
  std::string compare_path;
  std::string title;
};

void print_warnings(const io::ReportPage& page) {
  for (const std::string& warning : page.warnings) {
    std::fprintf(stderr, "stridemap: warning: %s\n", printable_text(warning).c_str());
  }
}

void run_report(const ReportArgs& args) {
  io::ReportPageOptions options;
  options.assets_dir = report_assets_dir();
  options.compare_path = args.compare_path;
  options.title = args.title;
  const std::string out = args.out_path.empty() ? (std::filesystem::path(args.directory) / "report.html").string()
                                                : args.out_path;
  const io::ReportPage page = io::write_report_page(args.directory, out, options);
  print_warnings(page);
  std::printf("report: %s (%.1f MB)\n", printable_text(out).c_str(), static_cast<double>(page.html.size()) / 1e6);
}

}  // namespace

std::string report_assets_dir() {
  std::error_code error;
  const std::vector<std::string> places = data_search_paths("web");
  std::string looked;
  for (const std::string& place : places) {
    // The source folder's web/ holds the page's script but not three.js.
    if (std::filesystem::is_regular_file(std::filesystem::path(place) / io::kReportThreeFile, error)) return place;
    looked += (looked.empty() ? "" : ", ") + std::filesystem::absolute(place, error).string();
  }
  throw InputError("report: the page's web assets (three.js, report.js) were not found (looked in " + looked +
                   "); build stridemap (its build runs npm ci in web/) or install it");
}

void write_run_report(const std::string& folder, const std::string& target) {
  io::ReportPageOptions options;
  options.assets_dir = report_assets_dir();
  // `folder` is the staging folder; the page is named after where it goes.
  options.title = "stridemap report: " + std::filesystem::path(target).lexically_normal().filename().string();
  print_warnings(io::write_report_page(folder, (std::filesystem::path(folder) / "report.html").string(), options));
}

CLI::Option* add_report_flag(CLI::App& command, bool& report) {
  return command.add_flag("--report", report,
                          "Also write report.html into the output folder: tables, pictures and the map in 3D, "
                          "one page that opens offline (stridemap report)");
}

void register_report(CLI::App& app) {
  auto args = std::make_shared<ReportArgs>();
  CLI::App* cmd = app.add_subcommand(
      "report", "One HTML page of a run's outputs: summary tables, pictures, and the map in interactive 3D "
                "(docs/outputs.md); opens offline from the file");
  cmd->add_option("DIR", args->directory, "A run's output folder (map.smap, summary.json, PNGs)")->required();
  cmd->add_option("--out", args->out_path, "The page to write (default DIR/report.html); an existing file must be "
                                           "a stridemap report page");
  cmd->add_option("--compare", args->compare_path,
                  "A second map shown side by side: a map file or a folder holding map.smap (default: the run's truth)");
  cmd->add_option("--title", args->title, "Heading of the page");
  cmd->callback([args] { run_report(*args); });
}

}  // namespace stridemap::cli
