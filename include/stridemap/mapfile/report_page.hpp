#pragma once
// The report page: one self-contained HTML file that shows a run's outputs
// (summary.json as tables, every PNG, and the map in an interactive 3D view
// drawn with three.js) and opens offline from disk (docs/outputs.md,
// "The report page"). The 3D library and the page's own script are read
// from `assets_dir` when the page is made and embedded whole; the map
// layers go in as little-endian binary, base64-encoded (float16 for the
// float layers), so a 500 x 500 map with its truth stays under 5 MB.
#include <string>
#include <vector>

namespace stridemap::io {

/// The files of assets_dir the page embeds.
inline constexpr const char* kReportThreeFile = "three.module.min.js";
inline constexpr const char* kReportOrbitFile = "OrbitControls.js";
inline constexpr const char* kReportScriptFile = "report.js";
inline constexpr const char* kReportStyleFile = "report.css";

struct ReportPageOptions {
  /// Folder holding the four files above (the build's share/stridemap/web,
  /// or the installed one). Required.
  std::string assets_dir;
  /// A second map shown beside the first: a map file, or a folder holding
  /// map.smap. Empty: the run's truth.csv when it has one, else none.
  std::string compare_path;
  /// Heading of the page; empty: "stridemap report: <folder name>".
  std::string title;
};

/// What build_report_page found, for the command's messages.
struct ReportPage {
  std::string html;
  /// Problems that did not stop the page (a damaged map file, a truth.csv
  /// of another shape): the page shows them too.
  std::vector<std::string> warnings;
};

/// Reads the run's outputs in `directory` (map.smap, summary.json, *.png,
/// truth.csv, path.csv) and builds the page. Throws InputError when the
/// folder does not exist, holds none of those files, or an asset is missing.
ReportPage build_report_page(const std::string& directory, const ReportPageOptions& options);

/// build_report_page, written to `path` (a temporary file renamed into
/// place). An existing file there that is not a stridemap report page is
/// refused, so a user's page is never replaced.
ReportPage write_report_page(const std::string& directory, const std::string& path, const ReportPageOptions& options);

/// The first line of every report page: how write_report_page knows one.
inline constexpr const char* kReportPageMarker = "<!DOCTYPE html><!-- stridemap report page -->";

}  // namespace stridemap::io
