#pragma once
// Where `stridemap map --window` and `live --window` put the map's window
// (docs/cli.md). By default it follows the robot (the paper's local map).
// CENTER fixes it with a given map-frame point in its centre cell; `fit`
// fixes it over everything the run measures, found by a first pass over the
// scans (FootprintPass) through the same pipeline as the mapping run, and
// grows the map beyond the configured size only when the run needs it.
#include <cstddef>
#include <limits>
#include <memory>
#include <string>

#include <Eigen/Core>

#include "stridemap/core/grid_map.hpp"
#include "stridemap/core/pose_track.hpp"
#include "stridemap/live/scan_mapper.hpp"
#include "stridemap/sensors/urg04lx.hpp"

namespace stridemap {

struct WindowChoice {
  enum class Mode { follow, center, fit };
  Mode mode = Mode::follow;
  Eigen::Vector2d center_m = Eigen::Vector2d::Zero();  ///< Mode::center [m]
};

/// "" (follow the robot), "fit", or "X,Y" in metres ("1.5,-0.2"). Throws
/// InputError naming `option` and saying what was expected.
WindowChoice parse_window_choice(const std::string& text, const std::string& option = "--window");

/// The x-y extent of the points and trunk positions of a run [m].
struct FootprintExtent {
  Eigen::Vector2d min_m = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector2d max_m = Eigen::Vector2d::Constant(-std::numeric_limits<double>::infinity());
  std::size_t points = 0;
  std::size_t poses = 0;

  bool empty() const { return points == 0 && poses == 0; }
  void add(double x_m, double y_m);
};

/// A fixed window: its size and its corner cell (smallest x and y).
struct WindowPlacement {
  int cells_per_side = 0;
  CellIndex min_cell{};
};

/// The window of the grid's size with `center_m` in its centre cell, as
/// ElevationMap::move_to places it.
WindowPlacement window_centred_at(const GridOptions& grid, const Eigen::Vector2d& center_m);

/// The smallest square window of at least grid.cells_per_side cells that
/// holds every cell the extent touches, the extent centred in it. Throws
/// GridSizeError when that needs more than kMaxGridCellsPerSide cells a side
/// (naming the extent, the cells and their memory), InputError for an empty
/// extent (no scan got a pose).
WindowPlacement window_fitting(const GridOptions& grid, const FootprintExtent& extent);

/// The first pass of `--window fit`: the scans go through the pipeline a
/// ScanMapper with the same options builds (sensor model, range
/// calibration, scan filters, pose interpolation, the mapper's checks), and
/// where each point would land is recorded instead of kept in a map.
class FootprintPass {
 public:
  /// Throws InputError for invalid options, as ScanMapper does.
  FootprintPass(const ScanMapperOptions& options, const UrgParameters& sensor);
  ~FootprintPass();
  FootprintPass(const FootprintPass&) = delete;
  FootprintPass& operator=(const FootprintPass&) = delete;

  /// `raw.time_s` on the poses' clock; the poses must be complete. Drops
  /// poses no longer needed from `poses`: give the pass its own copy.
  void add(const UrgRawScan& raw, PoseTrack& poses);
  /// Ends the stream (a scan-sequence filter's held scan) and returns the extent.
  const FootprintExtent& finish();
  /// Scans that reached the mapper so far.
  std::size_t scans_placed() const;

 private:
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace stridemap
