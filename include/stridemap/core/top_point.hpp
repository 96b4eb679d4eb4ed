#pragma once
// Where in its cell the highest reading lies. Eq. (10) keeps a cell's
// highest reading, and at an object's edge that reading sits somewhere
// inside the cell: on the box's top a few millimetres in from the edge, or
// on its face exactly at the edge. The cell index alone places the edge to
// a whole cell; this pair of layers keeps the map-frame x and y of the
// reading that set the cell's elevation, so that an edge can be fitted to
// sub-cell precision (experiments/box_edges.hpp). The layers are ordinary
// declared layers (map_layer.hpp): they move, reset and copy with the map.
// They are written beside the update rule, never by it, so the heights a
// map stores are the same with or without them, bit for bit.
#include <cstddef>
#include <span>

#include <Eigen/Core>

#include "stridemap/core/grid_map.hpp"
#include "stridemap/core/map_layer.hpp"

namespace stridemap {

/// "top_point_x" and "top_point_y" [m], NaN until a reading sets the cell;
/// not in the planner's default export.
LayerSpec top_point_x_layer();
LayerSpec top_point_y_layer();

/// The two layers of one map, found once per scan; then a point costs a
/// slot look-up and a float compare.
class TopPoints {
 public:
  /// Declares the layers in `map` when it does not have them yet (this
  /// allocates: declare them before mapping, e.g. in GridOptions::extra_layers).
  explicit TopPoints(ElevationMap& map);

  /// After the mapper applied a reading at (x, y) of height h: when the
  /// cell holds it as its elevation (it was the first, or the highest so
  /// far), the cell keeps its position. A later reading of the same height
  /// moves it, an equal-height tie. False when the reading did not set the
  /// cell or lies outside the window.
  bool note(ElevationMap& map, double x_m, double y_m, double h_m) const {
    std::size_t slot = 0;
    if (!map.slot_at(x_m, y_m, slot)) return false;
    if (map.state_data()[slot] != static_cast<std::uint8_t>(CellState::measured)) return false;
    if (map.elevation_data()[slot] != static_cast<float>(h_m)) return false;
    map.data(x_)[slot] = static_cast<float>(x_m);
    map.data(y_)[slot] = static_cast<float>(y_m);
    return true;
  }
  /// note() for each map-frame point of a scan, after the scan was
  /// integrated; returns how many set their cell.
  std::size_t note_all(ElevationMap& map, std::span<const Eigen::Vector3d> points_m) const;

  LayerId<float> x_layer() const { return x_; }
  LayerId<float> y_layer() const { return y_; }

 private:
  LayerId<float> x_;
  LayerId<float> y_;
};

}  // namespace stridemap
