#pragma once
// The local, robot-centred terrain map (paper section 5.1): an N x N grid of
// cells with an elevation layer, a certainty layer, a cell state, the update
// rule's bookkeeping and any layer a user declares (map_layer.hpp).
//
// Cells are addressed by a global integer index (floor of the map-frame
// coordinate divided by the cell size), so a cell keeps its index however the
// window moves. The window covers N consecutive indices on each axis and is
// stored as a circular buffer: a cell lives in slot (ix mod N, iy mod N).
// Moving the window therefore never copies the grid; the slots of the cells
// that leave are exactly the slots of the cells that enter, and are reset.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "stridemap/core/error.hpp"
#include "stridemap/core/map_layer.hpp"

namespace stridemap {

enum class CellState : std::uint8_t {
  unknown = 0,   ///< never plausibly measured (certainty 0, elevation NaN)
  measured = 1,  ///< updated by at least one measurement (certainty > 0)
  filled = 2,    ///< unknown, elevation estimated from neighbours (eq. 11)
};

struct GridOptions {
  /// N: cells per side. The paper uses 100 x 100.
  int cells_per_side = 100;
  /// Edge length of a cell [m]: 10 mm for the URG on Messor, 5 mm for
  /// structured light on Ragno (paper section 5.1).
  double cell_size_m = 0.01;
  /// Layers the map holds beyond builtin_layers(), in this order; empty by
  /// default. A mapper's map is made from these options, so a layer
  /// declared here is there from the first scan (see ElevationMap::layer).
  std::vector<LayerSpec> extra_layers = {};
};

/// Appends `spec` to grid.extra_layers unless a layer of its name is there:
/// a helper that declares its layers may be called more than once.
void declare_layer_once(GridOptions& grid, const LayerSpec& spec);

/// The grids a map accepts. The map is held several times over (snapshots for
/// a planner, the fill-in's copy, a test bed's truth layers), so its own
/// layers are kept to a few hundred MB: at most kMaxGridCellsPerSide cells a
/// side, 4096 x 4096 x kGridBytesPerCell = 335.5 MB. Cells from 0.1 mm to 10 m:
/// finer is below any range sensor's noise, coarser is no terrain map.
inline constexpr int kMaxGridCellsPerSide = 4096;
inline constexpr double kMinCellSizeM = 1e-4;
inline constexpr double kMaxCellSizeM = 10.0;
/// Bytes of the built-in layers of one cell (elevation, certainty, state,
/// the gated rule's bookkeeping, the running mean and its count); layers a
/// user adds come on top.
inline constexpr std::size_t kGridBytesPerCell = 4 + 4 + 1 + 1 + 4 + 4 + 2;

/// A grid too large for memory or too coarse or fine to be a map, refused
/// before anything is allocated. An InputError, so it reaches a user as one;
/// its own type so that a caller can name the setting that chose the size.
class GridSizeError : public InputError {
 public:
  using InputError::InputError;
};

/// Throws GridSizeError naming the field, the value and, for too many
/// cells, the memory they would take ("20000 x 20000 cells need 8.0 GB").
void validate_grid_options(const GridOptions& options);
/// The cells per side a square window needs to cover `extent_m` with cells
/// of `cell_size_m`, checked before any conversion: throws GridSizeError
/// with the memory it would take ("a 0.1 mm map of this 2.10 m area needs
/// 21000 x 21000 cells, 8.8 GB") when that is beyond the limits above.
int cells_per_side_to_cover(double extent_m, double cell_size_m);
/// "8.8 GB", "336 MB", "20 kB": bytes for a message.
std::string byte_size_text(double bytes);

struct CellIndex {
  std::int64_t x = 0;
  std::int64_t y = 0;
  friend bool operator==(const CellIndex&, const CellIndex&) = default;
};

class ElevationMap {
 public:
  /// Throws InputError when the options are not a usable grid.
  explicit ElevationMap(const GridOptions& options = {});

  int cells_per_side() const { return n_; }
  double cell_size_m() const { return cell_size_m_; }
  /// Global index of the window's corner cell (smallest x and y).
  CellIndex min_cell() const { return min_cell_; }

  /// Global index of the cell that contains (x, y); no bounds check.
  CellIndex cell_of(double x_m, double y_m) const;
  bool contains(CellIndex cell) const;
  /// Centre of a cell in the map frame.
  Eigen::Vector2d cell_center(CellIndex cell) const;

  /// Moves the window by whole cells so that (x, y) lies in its centre cell.
  /// Returns the number of cells reset. Non-finite input leaves it in place
  /// and returns 0.
  std::size_t move_to(double x_m, double y_m);
  /// Moves the window so that its corner cell becomes `min_cell`.
  std::size_t move_corner_to(CellIndex min_cell);
  /// Forgets everything (all cells unknown), keeping the window.
  void clear();

  /// Slot of a cell inside the window in the storage arrays.
  std::size_t slot(CellIndex cell) const {
    return static_cast<std::size_t>(wrap(cell.x) * n_ + wrap(cell.y));
  }
  /// Slot of the cell holding (x, y), false when it lies outside the
  /// window. The per-point fast path: no division, no modulo.
  bool slot_at(double x_m, double y_m, std::size_t& slot_out) const {
    const double fx = x_m * inverse_cell_size_;
    const double fy = y_m * inverse_cell_size_;
    const auto lo_x = static_cast<double>(min_cell_.x), lo_y = static_cast<double>(min_cell_.y);
    if (!(fx >= lo_x && fx < lo_x + n_ && fy >= lo_y && fy < lo_y + n_)) return false;
    // Truncation plus a correction is floor() without a libm call; the
    // range check above keeps the conversion defined.
    const auto tx = static_cast<std::int64_t>(fx), ty = static_cast<std::int64_t>(fy);
    int i = static_cast<int>(tx - (fx < static_cast<double>(tx)) - min_cell_.x) + min_slot_x_;
    int j = static_cast<int>(ty - (fy < static_cast<double>(ty)) - min_cell_.y) + min_slot_y_;
    if (i >= n_) i -= n_;
    if (j >= n_) j -= n_;
    slot_out = static_cast<std::size_t>(i) * static_cast<std::size_t>(n_) + static_cast<std::size_t>(j);
    return true;
  }
  /// Global index of the cell at local position (i, j) from the corner.
  CellIndex cell_at_local(int i, int j) const { return {min_cell_.x + i, min_cell_.y + j}; }

  float elevation(CellIndex cell) const { return data(layers::elevation)[slot(cell)]; }
  /// Mean of the readings eq. (9) accepted in the cell (NaN when unknown).
  /// Eq. (10) keeps the highest reading, which is what an obstacle-averse
  /// planner wants but lies above the surface by the noise (about one
  /// standard deviation after a few hits); this mean does not, which is what
  /// the robot's own height reference needs (sim/pose_estimate.hpp).
  float mean_elevation(CellIndex cell) const { return data(layers::mean_elevation)[slot(cell)]; }
  float certainty(CellIndex cell) const { return data(layers::certainty)[slot(cell)]; }
  CellState state(CellIndex cell) const { return static_cast<CellState>(data(layers::state)[slot(cell)]); }

  // --- The layer registry (map_layer.hpp) ---

  /// Declares a layer after construction; every cell gets its reset value.
  /// Throws InputError for an unusable declaration or a name already used.
  /// Allocates: call it before mapping, not per scan.
  std::size_t add_layer(const LayerSpec& spec);
  std::size_t layer_count() const { return layers_.size(); }
  const LayerSpec& layer_spec(std::size_t index) const { return layers_[index].spec; }
  /// The layer's place, or nothing when the map has no layer of that name.
  std::optional<std::size_t> find_layer(std::string_view name) const;
  /// A typed handle to the named layer, looked up once outside any loop.
  /// Throws InputError when there is no such layer (the message lists the
  /// layers there are) or it holds another type.
  template <typename T>
  LayerId<T> layer(std::string_view name) const {
    return LayerId<T>{checked_layer(name, layer_type_of<T>())};
  }
  /// "elevation, certainty, ...": the layers' names for messages.
  std::string layer_names() const;

  // Storage, indexed by slot(). For the update rule, filters and a user's
  // own layers; a slot holds its layer's reset value until updated.
  template <typename T>
  T* data(LayerId<T> id) {
    return storage<T>(layers_[id.index]).data();
  }
  template <typename T>
  const T* data(LayerId<T> id) const {
    return storage<T>(layers_[id.index]).data();
  }
  /// A layer's elements as bytes, whatever its type (for readers and writers).
  void* layer_bytes(std::size_t index);
  const void* layer_bytes(std::size_t index) const;

  float* elevation_data() { return data(layers::elevation); }
  float* certainty_data() { return data(layers::certainty); }
  std::uint8_t* state_data() { return data(layers::state); }
  const float* elevation_data() const { return data(layers::elevation); }
  const float* certainty_data() const { return data(layers::certainty); }
  const std::uint8_t* state_data() const { return data(layers::state); }

  /// Bookkeeping of the gated elevation rule (map_update.hpp): readings that
  /// contradicted the cell since its last plausible one, and their maximum.
  std::uint8_t* contradiction_data() { return data(layers::contradictions); }
  float* pending_elevation_data() { return data(layers::pending_elevation); }
  /// The running mean of accepted readings and how many it holds.
  float* mean_elevation_data() { return data(layers::mean_elevation); }
  std::uint16_t* mean_count_data() { return data(layers::mean_count); }
  const float* mean_elevation_data() const { return data(layers::mean_elevation); }
  const std::uint8_t* contradiction_data() const { return data(layers::contradictions); }
  const float* pending_elevation_data() const { return data(layers::pending_elevation); }
  const std::uint16_t* mean_count_data() const { return data(layers::mean_count); }

  /// Every layer of the slot back to its reset value.
  void reset_slot(std::size_t s) {
    for (Layer& layer : layers_) reset(layer, s);
  }
  /// Every layer of the slot but the derived ones back to its reset value:
  /// the cell unknown, as if never measured (the visibility clean-up's
  /// clearing).
  void forget_measurement(std::size_t s) {
    for (Layer& layer : layers_) {
      if (!layer.derived) reset(layer, s);
    }
  }
  /// Marks a layer as derived: recomputed from the others by a keeper that
  /// tells what to redo by comparing with the values it last wrote (the
  /// foothold layers), so forget_measurement() leaves it to the keeper.
  /// Copies keep the mark; a map file does not (the keeper marks its
  /// layers again when it takes a loaded map).
  void mark_derived(std::size_t layer) { layers_[layer].derived = true; }
  bool derived(std::size_t layer) const { return layers_[layer].derived; }

 private:
  std::int64_t wrap(std::int64_t v) const {
    const std::int64_t m = v % n_;
    return m < 0 ? m + n_ : m;
  }

  void set_min_cell(CellIndex c) {
    min_cell_ = c;
    min_slot_x_ = static_cast<int>(wrap(c.x));
    min_slot_y_ = static_cast<int>(wrap(c.y));
  }

  // One declared layer and its elements; only the vector of its type is used.
  struct Layer {
    LayerSpec spec;
    bool derived = false;
    float reset_f32 = 0.0f;
    std::uint16_t reset_u16 = 0;
    std::uint8_t reset_u8 = 0;
    std::vector<float> f32;
    std::vector<std::uint16_t> u16;
    std::vector<std::uint8_t> u8;
  };
  static void reset(Layer& layer, std::size_t s) {
    switch (layer.spec.type) {
      case LayerType::f32: layer.f32[s] = layer.reset_f32; break;
      case LayerType::u16: layer.u16[s] = layer.reset_u16; break;
      case LayerType::u8: layer.u8[s] = layer.reset_u8; break;
    }
  }
  template <typename T>
  static std::vector<T>& storage(Layer& layer) {
    if constexpr (std::is_same_v<T, float>) return layer.f32;
    else if constexpr (std::is_same_v<T, std::uint16_t>) return layer.u16;
    else return layer.u8;
  }
  template <typename T>
  static const std::vector<T>& storage(const Layer& layer) {
    if constexpr (std::is_same_v<T, float>) return layer.f32;
    else if constexpr (std::is_same_v<T, std::uint16_t>) return layer.u16;
    else return layer.u8;
  }
  std::size_t checked_layer(std::string_view name, LayerType type) const;
  void reset_rows(std::size_t begin_row, std::size_t end_row);
  void fill_with_reset(Layer& layer);

  int n_;
  double cell_size_m_;
  double inverse_cell_size_;
  CellIndex min_cell_{};
  int min_slot_x_ = 0, min_slot_y_ = 0;  // wrap(min_cell_), kept for slot_at
  std::vector<Layer> layers_;  // builtin_layers() first, at the places layers:: names
};

}  // namespace stridemap
