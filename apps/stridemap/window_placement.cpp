#include "window_placement.hpp"

#include <cstdio>
#include <string>

#include "stridemap/recordings/pose_stream.hpp"
#include "terminal_output.hpp"

namespace stridemap::cli {

void fix_window(ScanMapperOptions& options, const WindowPlacement& placement) {
  options.config.mapper.follow_robot = false;
  options.config.mapper.grid.cells_per_side = placement.cells_per_side;
  options.window_corner = placement.min_cell;
}

void fit_window(ScanMapperOptions& options, const std::string& log_path, const std::string& poses_path,
                double max_pose_gap_s, LiveClock clock) {
  io::PoseFileCursor pose_file(poses_path);  // a pass of its own, streamed like the mapping's
  PoseTrack poses(max_pose_gap_s);
  io::ScanLogReader reader(log_path);
  const UrgScan* scan = reader.next();
  if (scan == nullptr) return;  // no scan: the mapping pass says so
  FootprintPass pass(options, scip::to_urg_parameters(reader.log().parameters));
  {
    io::ProgressBar bar = progress_bar("fit", "scans");
    UrgRawScan raw;
    for (; scan != nullptr; scan = reader.next()) {
      raw = scan->raw;
      raw.time_s = clock == LiveClock::sensor ? sensor_time_seconds(scan->sensor_time_ms) : scan->host_time_s;
      pose_file.read_to(raw.time_s, poses);
      pass.add(raw, poses);
      bar.update(reader.scans(), 0);
    }
  }
  const FootprintExtent& extent = pass.finish();
  const GridOptions& grid = options.config.mapper.grid;
  const WindowPlacement placement = window_fitting(grid, extent);
  if (!verbosity().quiet) {
    char line[400];
    std::snprintf(line, sizeof line,
                  "stridemap: --window fit: %zu points of %zu scans lie in x %.2f..%.2f m, y %.2f..%.2f m; the "
                  "window is %d x %d cells of %.1f mm (%.2f m a side)%s\n",
                  extent.points, pass.scans_placed(), extent.min_m.x(), extent.max_m.x(), extent.min_m.y(),
                  extent.max_m.y(), placement.cells_per_side, placement.cells_per_side, grid.cell_size_m * 1000.0,
                  placement.cells_per_side * grid.cell_size_m,
                  placement.cells_per_side > grid.cells_per_side
                      ? (", grown from " + std::to_string(grid.cells_per_side) + " to hold them").c_str()
                      : "");
    std::fputs(line, stderr);
  }
  fix_window(options, placement);
}

}  // namespace stridemap::cli
