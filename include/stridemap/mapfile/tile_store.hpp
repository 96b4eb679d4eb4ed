#pragma once
// A map larger than the window: the cells that leave the robot-centred
// window go to tiles on disk, and come back bit for bit when the window
// covers them again (docs/global_map.md). A tile is a map file
// (mapfile/map_file.hpp) of GlobalMapOptions::tile_cells cells a side whose
// corner cell is (tx, ty) * tile_cells, so tiles line up with the map's
// cell grid whatever the window does. A few tiles are kept in memory
// (least recently used pushed out first); a changed tile is written as soon
// as the window no longer reaches it, so a run killed at any time leaves
// on disk every cell but those of the window and of the few tiles it
// touches (docs/global_map.md). A tile is written atomically
// (temporary file, rename) and only ever into a folder the store found new
// or empty, so it never replaces a file this run did not create.
//
// Disk faults do not end a run. A tile whose write fails (a full disk, the
// folder gone) stays in memory, and the store writes nothing more until
// flush() tries again; a tile that cannot be read back (damaged, deleted)
// is renamed "<name>.damaged", and its cells start unknown and are mapped
// anew. Each is told once through take_notices(); unsaved() says what a run
// would lose if it ended now. The manifest lists every tile written, so
// that merge_tiles() can name a tile that went missing.
//
// The store listens to the mapper's window moves (core/window_move_listener.hpp).
// A move whose cells stay within tiles already in memory, or that enter
// tiles never written, reads no file and allocates nothing: the cache's
// memory is taken when the store is made.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <set>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "stridemap/config/global_map_options.hpp"
#include "stridemap/core/grid_map.hpp"
#include "stridemap/core/tile_grid.hpp"
#include "stridemap/core/window_move_listener.hpp"
#include "stridemap/mapfile/map_file.hpp"

namespace stridemap::io {

using stridemap::TileIndex;  // core/tile_grid.hpp

/// Throws InputError naming `options.folder` when a TileStore would refuse
/// it (a file, a folder that cannot be read or holds anything: an earlier
/// run's global map is named with its tile and cell sizes, beside this
/// run's `cell_size_m` when known), and for bad options. Creates nothing:
/// a command calls it before it connects to a sensor or writes an output,
/// so that a refused run has done neither.
void check_global_map_folder(const GlobalMapOptions& options, std::optional<double> cell_size_m);

/// "tile_<x>_<y>.smap": a tile's file name in the folder.
std::string tile_file_name(TileIndex tile);
/// The file naming the folder's tile size and cell size (global_map.json).
inline constexpr const char* kGlobalMapManifest = "global_map.json";

struct TileStoreStats {
  std::size_t tiles_written = 0;   ///< tile files written (each write counted)
  std::size_t tiles_read = 0;      ///< tile files read back
  std::size_t tiles_on_disk = 0;   ///< distinct tile files the store created
  std::size_t cells_saved = 0;     ///< cells copied from the window into tiles
  std::size_t cells_restored = 0;  ///< cells copied from tiles into the window
  std::size_t write_failures = 0;  ///< tile or manifest writes that failed (each tried again later)
  std::size_t tiles_set_aside = 0; ///< tiles that could not be read back, renamed "<name>.damaged"
};

class TileStore final : public WindowMoveListener {
 public:
  /// `like` gives the cell size and the layers every tile holds (those of
  /// the window it will serve); `metadata` goes into every tile file.
  /// Creates the folder, or takes it when it exists and is empty, and
  /// writes the manifest. Throws InputError naming the folder when it is a
  /// file, holds anything, or cannot be created, and for bad options.
  TileStore(const GlobalMapOptions& options, const ElevationMap& like, MapFileMetadata metadata);

  void window_leaving(const ElevationMap& map, CellIndex new_min) override;
  void window_entered(ElevationMap& map, CellIndex old_min) override;

  /// Copies every cell of `window` into its tile and writes every tile
  /// changed since it was last written: afterwards the tiles on disk hold
  /// the whole map. Call at the end of a run (and whenever the disk should
  /// catch up); on its own the store writes a tile when the window leaves
  /// it (or, with a small cache, when it is pushed out of memory).
  void flush(const ElevationMap& window);

  /// Changed tiles (and the manifest) not on disk because their last write
  /// failed: what a run ending now would lose. flush() tries them again.
  std::size_t unsaved() const;
  /// True from a failed write until a flush() writes everything.
  bool failing() const { return failing_; }
  /// What went wrong since the last call, one line each, naming the file:
  /// a write that failed, writes working again, a tile set aside.
  std::vector<std::string> take_notices();

  const std::string& folder() const { return options_.folder; }
  int tile_cells() const { return options_.tile_cells; }
  /// The tile holding a cell.
  TileIndex tile_of(CellIndex cell) const;
  std::string tile_path(TileIndex tile) const;
  const TileStoreStats& stats() const { return stats_; }
  /// Tiles the store wrote, in order.
  const std::set<TileIndex>& tiles_on_disk() const { return on_disk_; }

 private:
  // A slot of the cache; every slot's map is allocated when the store is
  // made, so that taking a tile into memory reuses one.
  struct Cached {
    TileIndex index;
    std::unique_ptr<ElevationMap> map;
    bool used = false;
    bool dirty = false;
    std::uint64_t last_use = 0;
  };
  struct CellRect {
    CellIndex min;
    CellIndex end;  // exclusive
    bool empty() const { return end.x <= min.x || end.y <= min.y; }
  };
  // Cells of `a`'s window outside `b`'s, as at most two rectangles.
  std::pair<CellRect, CellRect> difference(CellIndex a_min, CellIndex b_min) const;
  void save_rect(const ElevationMap& map, const CellRect& rect);
  void restore_rect(ElevationMap& map, const CellRect& rect);
  // The cached tile, read from disk or made blank when `create`; nullptr
  // when the tile holds nothing and `create` is off.
  Cached* tile(TileIndex index, bool create);
  bool holds_data(const ElevationMap& map, const CellRect& rect) const;
  // Writes every changed tile the window at `new_min` does not reach.
  void write_tiles_left(CellIndex new_min);
  // False (the tile stays dirty, a notice told) when the write failed.
  bool write(Cached& tile);
  // Frees a slot for another tile; a changed tile that cannot be written
  // goes to unsaved_ rather than being lost.
  void evict(Cached& slot);
  std::string manifest_path() const;
  std::string manifest_text() const;  // lists the tiles on disk
  bool write_manifest();
  void note_write_failure(const std::string& what);
  void read(TileIndex index, ElevationMap& into);
  void set_aside(TileIndex index, const std::string& why);

  GlobalMapOptions options_;
  MapFileMetadata metadata_;
  GridOptions tile_grid_;
  int window_cells_ = 0;
  ElevationMap reset_cell_;  // one cell at every layer's reset value
  std::vector<std::size_t> layer_bytes_;
  std::vector<Cached> cache_;
  std::set<TileIndex> on_disk_;
  std::uint64_t clock_ = 0;
  TileStoreStats stats_;
  std::vector<Cached> unsaved_;  // changed tiles pushed out of the cache while writes failed
  bool manifest_dirty_ = false;  // a tile was added to on_disk_ since the manifest was written
  bool failing_ = false;
  std::vector<std::string> notices_;
};

struct MergedTiles {
  ElevationMap map;
  /// Tiles the manifest lists that are missing, and tiles that could not be
  /// read or do not fit, one line each naming the file: where the map has
  /// holes. Empty for a whole global map.
  std::vector<std::string> holes;
};

/// Loads every tile of a folder a TileStore wrote into one map covering
/// them all (the window's cell size and layers); a tile that is missing or
/// damaged leaves a hole, named in `holes`. Throws InputError naming the
/// folder when it has no valid manifest or no readable tile, and
/// GridSizeError when the tiles span more than kMaxGridCellsPerSide cells.
MergedTiles merge_tiles(const std::string& folder);

}  // namespace stridemap::io
