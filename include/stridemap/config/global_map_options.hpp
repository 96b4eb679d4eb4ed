#pragma once
// Settings of the global map kept beyond the robot-centred window
// (mapfile/tile_store.hpp): the YAML `global_map:` section and `--global-map`.
#include <string>

namespace stridemap {

struct GlobalMapOptions {
  /// Folder the tiles go to; empty (the default) keeps no global map. It
  /// must not exist yet or be empty: the store writes only files it created.
  std::string folder{};
  /// Cells per side of a tile. 100 is 1 m at the paper's 1 cm cells, the
  /// paper's window, so a window touches at most four tiles at once; a tile
  /// file with every layer (foothold ones included) is about 400 kB.
  int tile_cells = 100;
  /// Tiles held in memory (allocated up front), the least recently used
  /// written out first. 16 covers the four a window touches and those it
  /// just left, so driving to and fro over a tile edge reads no file.
  int cached_tiles = 16;
  /// Scan time (s) between two saves of the window and its tiles while
  /// mapping (live::ScanMapper), so that a run killed while the robot stays
  /// on the same few tiles loses at most this much; tiles the window left
  /// are written at once anyway. 0: only those and the end of the run.
  double save_interval_s = 60.0;
};

/// Throws InputError naming the field when a setting is out of range
/// (tile_cells 1..4096, cached_tiles 1..1024, save_interval_s 0..86400).
void validate_global_map_options(const GlobalMapOptions& options);

}  // namespace stridemap
