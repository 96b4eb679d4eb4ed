#pragma once
// What has moved: a visibility clean-up beyond the paper. Eq. (10) keeps a
// cell's highest reading, so an object taken away, or a foot that passed
// through the scan, would stand in the map for ever. A beam that travelled
// from the sensor to its hit proves the space along its way empty; a cell
// whose stored height lies above that way by more than the uncertainty is
// contradicted, and a cell contradicted often enough is cleared (unknown:
// the next reading there is taken as it is, eq. 9's first case).
//
// The rule, per beam with sensor origin o, hit p, range r, range error Dr
// and the sensor's height-error bound e at the hit (eq. 6's error terms):
//   - the beam's cells are those its horizontal projection crosses, walked
//     from o towards p (Amanatides-Woo), and only those whose whole crossing
//     lies at ranges <= r - Dr: the true surface may be anywhere within Dr
//     of the hit, so a cell that may hold it is never touched;
//   - the beam's height over a cell is its highest over the crossing (at the
//     entry or the exit), z_beam;
//   - the cell is contradicted when its elevation h > z_beam + margin, with
//     margin = uncertainty_factor * e + relief_factor * cell_size: the
//     sensor's bound, plus the relief a cell may hold beside the beam's path
//     (its height is the highest reading anywhere in it);
//   - once per scan a contradicted measured cell loses certainty_decrement
//     of its certainty (eq. 9's scale); at 0 it is cleared. A filled cell
//     (eq. 11) carries no certainty and is cleared at once.
// Beams are thinned to one per beam_spacing_cells cells between hits: the
// fan's neighbouring beams cross the same cells, and a cell counts once per
// scan anyway. docs/visibility.md has the measurements behind the defaults.
//
// The walk is pruned, exactly: a cell can only be contradicted where the
// beam runs lower than the cell's height, so each beam's walk starts where
// the beam has come down to the highest elevation the rows and columns it
// crosses hold (and a rising beam's walk ends where it has risen above it);
// the bound is taken from the window's highest cell first, then again over
// the rows and columns left of the walk, a few times, as the start moves on.
// Those maxima are upper bounds for the whole scan (the clean-up itself
// only lowers cells). begin_scan(map) takes them from the whole map;
// begin_scan(mapper) keeps them up to date from the mapper's changed rows
// (raised by the cells written since; a row or column that lost its highest
// cell, to the clean-up or to a window move, taken again: each column keeps
// the slot row of the cell that set its maximum, so that a window move takes
// again only the columns whose highest cell left, not every column no
// higher than the rows that left, which on a long walk were often over a
// quarter of them and sent the scan to the whole map) and falls back to
// the whole map when the mapper counted a change its rows do not show
// (TerrainMapper::changes()). A bound may stay above its row's highest cell
// (a reading that lowered a cell), never below it. A walk also
// ends where it leaves the window for good: no cell beyond can be touched.
// The window's highest cell is tried before the beam's range is taken (a
// square root and a division): a falling beam that comes down to it only at
// t >= 1 ends before it (its walk stops by t = 1 for a range error >= 0),
// a rising or level one starting more than the margin above it stays so.
// The walk is a step of its own, entered only by the beams the bounds
// leave; trace_fan() runs a whole fan's beams in one loop, the origin
// checked once. Where the CPU has AVX2 it first picks out the beams to
// trace (the thinning and validity), then screens them four at a time
// with the very tests and bound rounds above, operation for operation
// (the bounds cannot change during the scan), finds where each walk left
// starts (its first cell past the skip) in the same lanes, and walks them
// in the fan's order, since a walk reads what the walks before it cleared.
// Every crossing parameter of the walk is computed from its cell boundary,
// not summed step by step, so a walk started part-way reaches the very
// cells and values the whole walk would: the pruning changes nothing. (Against
// the summed crossings of the walk before it, which may differ from these
// in the last bit, the results were the same bit for bit on every random
// and simulated run: tests/core/visibility_pruning_test.cpp.)
#include <cstddef>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "stridemap/core/cell_box.hpp"
#include "stridemap/core/grid_map.hpp"

namespace stridemap {

struct VisibilityOptions {
  /// Clear what beams pass below (MappingPipeline, ScanIntegrator). Off by
  /// default: docs/visibility.md has what it costs and what it lowers.
  bool enabled = false;
  /// Factor on the sensor's height-error bound e in the margin. The bound
  /// is already a worst case (eq. 6), so 1.
  double uncertainty_factor = 1.0;
  /// The margin's share from the cell's extent, in cell sizes: a cell's
  /// height is its highest reading, which may lie beside the beam's path
  /// inside the cell; 1 allows a 45 deg face across the whole cell.
  double relief_factor = 1.0;
  /// Certainty a contradicted cell loses per scan; with the paper's
  /// increment a = 3, equal to one plausible reading.
  double certainty_decrement = 3.0;
  /// Trace a beam only when its hit lies at least this many cells from the
  /// last traced beam's hit (0: every beam). Half a cell keeps the traced
  /// paths less than a cell apart, so that no cell near the hits falls
  /// between two of them.
  double beam_spacing_cells = 0.5;
};

/// Throws InputError naming the field ("visibility: relief_factor must be
/// ...") for a non-finite or negative value or a decrement of 0.
void validate_visibility_options(const VisibilityOptions& options);

/// One beam as the clean-up needs it: all in the map frame.
struct VisibilityBeam {
  Eigen::Vector3d origin_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d hit_m = Eigen::Vector3d::Zero();
  double range_error_m = 0.0;   ///< Dr: the hit may lie this much nearer [m]; below -1000 ranges the beam is not traced
  double height_error_m = 0.0;  ///< e: the sensor's height-error bound at the hit [m]
};

/// A scan's beams from one origin as the mapper keeps their hits
/// (TerrainMapper::BeamHits): arrays of `count` values each, map frame.
struct VisibilityFan {
  Eigen::Vector3d origin_m = Eigen::Vector3d::Zero();
  std::size_t count = 0;
  const double* x_m = nullptr;  ///< hits
  const double* y_m = nullptr;
  const double* z_m = nullptr;
  const double* height_error_m = nullptr;  ///< e of each
  const double* range_error_m = nullptr;   ///< Dr of each
};

/// A cell the clean-up cleared, with the height it had.
struct ClearedCell {
  CellIndex cell;
  float elevation_m = 0.0f;
};

/// What one scan's clean-up did.
struct VisibilityStats {
  std::size_t beams_traced = 0;
  std::size_t cells_crossed = 0;       ///< window cells walked (a cell once per beam)
  std::size_t cells_contradicted = 0;  ///< distinct cells the scan's beams passed below
  std::size_t cells_cleared = 0;       ///< of those, cleared to unknown
  /// The row and column maxima were taken from the whole map this scan
  /// (begin_scan(map), or begin_scan(mapper) when its changed rows did not
  /// hold every change), not kept up to date from the changed rows.
  bool maxima_from_whole_map = false;
};

class TerrainMapper;

class VisibilityClearing {
 public:
  /// Scratch sized for the map's window (allocated here, never per scan).
  /// Throws InputError for bad options.
  VisibilityClearing(const ElevationMap& map, const VisibilityOptions& options);

  /// Starts a scan on `map` (after the scan's readings were applied): every
  /// cell may be contradicted once again, the highest elevation of each row
  /// and column of the window is taken (one pass over the elevation layer),
  /// and the per-scan constants of the walk (cell size, window corner) are
  /// kept. Until the scan's last trace() the map must change only by the
  /// clean-up. Throws InputError for a map of another window size.
  void begin_scan(const ElevationMap& map);
  /// The same on mapper.map(), with the maxima kept up to date from the
  /// mapper's changed rows since the last begin_scan(mapper) on it, when
  /// its changes() say they hold every change; from the whole map when not
  /// (another mapper, a write through map(), a window move with a listener,
  /// changed rows cleared with cells not yet seen here). The clean-up's
  /// own writes must go through mapper.map_without_raising().
  void begin_scan(const TerrainMapper& mapper);
  /// Traces one beam on the map given to begin_scan(). Beams must come in
  /// the sensor's order for the thinning to keep the fan covered.
  void trace(ElevationMap& map, const VisibilityBeam& beam) {
    if (!thinned(beam.hit_m.x(), beam.hit_m.y())) trace_unthinned(map, beam);
  }
  /// trace() for a beam the caller already found not thinned() (by its
  /// hit's x and y), so that the fan's check runs once a beam.
  void trace_unthinned(ElevationMap& map, const VisibilityBeam& beam);
  /// trace() for each beam of a fan in its order, the same beams traced
  /// and the same results, at less cost a beam.
  void trace_fan(ElevationMap& map, const VisibilityFan& fan);
  /// Whether trace() would leave out a beam ending at `hit_m` (map x, y)
  /// for the thinning: a caller may skip forming the rest of such a beam.
  bool thinned(const Eigen::Vector2d& hit_m, double cell_size_m) const {
    return have_last_hit_ && options_.beam_spacing_cells > 0.0 &&
           (hit_m - last_hit_).squaredNorm() < spacing_m2(cell_size_m);
  }
  /// The same for the map given to begin_scan(), its spacing taken there.
  bool thinned(double hit_x_m, double hit_y_m) const {
    const double ex = hit_x_m - last_hit_.x(), ey = hit_y_m - last_hit_.y();
    return have_last_hit_ && ex * ex + ey * ey < spacing_m2_;
  }
  /// The scan's account since begin_scan(): the cells cleared in cleared()
  /// (up to a fixed number), the box of every cell it changed in changed().
  const VisibilityStats& stats() const { return stats_; }
  const std::vector<ClearedCell>& cleared() const { return cleared_; }
  const CellBox& changed() const { return changed_; }
  const VisibilityOptions& options() const { return options_; }
  /// Scans begun so far: tells a reader whether stats() are new.
  std::uint64_t scans() const { return scans_; }
  /// Cells of the window it was made for.
  std::size_t window_cells() const { return stamp_.size(); }

 private:
  void trace_from(ElevationMap& map, const Eigen::Vector3d& origin_m, const Eigen::Vector3d& hit_m,
                  double range_error_m, double height_error_m);
  /// trace_from() for a valid beam, already counted: d = hit - origin,
  /// range2 its squared norm.
  void trace_valid(ElevationMap& map, const Eigen::Vector3d& origin_m, const Eigen::Vector3d& d, double range2,
                   double range_error_m, double height_error_m);
  /// A walk's beam o + t d (in cells): ix, iy are floor(ox), floor(oy) and
  /// inverse_dx, inverse_dy 1 / dx, 1 / dy (any value for a 0), taken
  /// where they are shared or at hand.
  struct WalkBeam {
    double ox, oy;
    std::int64_t ix, iy;
    double dx, dy, inverse_dx, inverse_dy, z0, dz, margin, t_skip, t_end;
    // Started: where the walk starts (past t_skip) found already: the
    // cell, window-local (i, j), its slot row (times n) and column, each
    // axis's next boundary and its crossing, and the first cell's entry.
    bool started = false;
    std::int64_t i = 0, j = 0, row = 0, column = 0;
    double boundary_x = 0.0, boundary_y = 0.0, next_x = 0.0, next_y = 0.0, t_in = 0.0;
  };
  /// Walks the window's cells the beam crosses from the one holding t_skip
  /// to the last ending at or before t_end.
  /// Inlined into its callers: the beam's values stay in registers.
  template <bool kRising>
  [[gnu::always_inline]] inline void walk(ElevationMap& map, const WalkBeam& beam);
  void contradict(ElevationMap& map, CellIndex cell, std::size_t slot);
  double spacing_m2(double cell_size_m) const {
    const double spacing_m = options_.beam_spacing_cells * cell_size_m;
    return spacing_m * spacing_m;
  }
  void start(const ElevationMap& map);
  void take_maxima(const ElevationMap& map);
  bool update_maxima(const TerrainMapper& mapper);
  void build_tables();
  /// Highest elevation of window rows (or columns) lo..hi, counted from the
  /// window's corner (0 <= lo <= hi < n): `table` is that axis's
  /// range-maximum table.
  float range_max(const std::vector<float>& table, std::int64_t lo, std::int64_t hi) const {
    const std::size_t level = floor_log2_[static_cast<std::size_t>(hi - lo + 1)];
    const float* t = table.data() + level * static_cast<std::size_t>(n_);
    const float a = t[lo], b = t[hi - (std::int64_t{1} << level) + 1];
    return a < b ? b : a;
  }

  VisibilityOptions options_;
  std::vector<std::uint32_t> stamp_;  // per slot: the scan that last contradicted it
  int n_ = 0;                         // cells per side of the window
  CellIndex corner_{};                // the window's corner cell and its slot, at begin_scan()
  std::int64_t slot_x0_ = 0, slot_y0_ = 0;
  // Taken at begin_scan() from the map's cell size: the same values each
  // beam computed before, once a scan.
  double inverse_cell_ = 1.0, relief_m_ = 0.0, spacing_m2_ = 0.0;
  double window_top_ = 0.0;  // the highest known elevation in the window (-inf: none)
  // Highest elevation per window row (one global x index, counted from the
  // corner) and per window column, as sparse tables for range maxima:
  // level l holds the maximum of 2^l consecutive rows from each, so any
  // range is two look-ups. slot_row_max_, slot_column_max_: the same per
  // slot row and column (x, y mod n), kept from scan to scan.
  std::vector<float> row_max_, column_max_, slot_row_max_, slot_column_max_;
  std::vector<std::uint8_t> retake_row_, retake_column_;  // per slot: take it again from the map
  // Per slot column: the slot row of a cell that set its maximum, so that
  // a window move retakes only the columns whose highest cell left.
  std::vector<std::int32_t> column_holder_;
  // What begin_scan(mapper) saw of the mapper (mapper 0: none), and the
  // corner the slot maxima were last brought up to date for.
  std::uint64_t seen_mapper_ = 0, seen_unrecorded_ = 0, seen_scans_ = 0;
  CellIndex maxima_corner_{};
  // The slot maxima and corner the tables were last built from.
  std::vector<float> tables_rows_, tables_columns_;
  CellIndex tables_corner_{};
  bool tables_valid_ = false;
  std::vector<std::uint8_t> floor_log2_;  // of 1..n
  std::uint32_t scan_ = 0;
  std::uint64_t scans_ = 0;
  bool have_last_hit_ = false;
  Eigen::Vector2d last_hit_{0.0, 0.0};
  std::vector<ClearedCell> cleared_;  // capacity fixed at construction
  CellBox changed_;
  VisibilityStats stats_;
};

}  // namespace stridemap
