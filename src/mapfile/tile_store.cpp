#include "stridemap/mapfile/tile_store.hpp"

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <optional>
#include <sstream>
#include <system_error>

#include <nlohmann/json.hpp>

#include "stridemap/core/error.hpp"
#include "stridemap/io/text_file.hpp"

namespace stridemap {

void validate_global_map_options(const GlobalMapOptions& o) {
  if (o.tile_cells < 1 || o.tile_cells > kMaxGridCellsPerSide) {
    throw InputError("global_map.tile_cells: expected a whole number from 1 to " +
                     std::to_string(kMaxGridCellsPerSide) + ", got " + std::to_string(o.tile_cells));
  }
  if (o.cached_tiles < 1 || o.cached_tiles > 1024) {
    throw InputError("global_map.cached_tiles: expected a whole number from 1 to 1024, got " +
                     std::to_string(o.cached_tiles));
  }
  if (!(o.save_interval_s >= 0.0 && o.save_interval_s <= 86400.0)) {
    throw InputError("global_map.save_interval_s: expected seconds from 0 to 86400, got " +
                     std::to_string(o.save_interval_s));
  }
}

}  // namespace stridemap

namespace stridemap::io {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// Cells [a, a + n) not in [b, b + n): one interval, as both are n long.
std::pair<std::int64_t, std::int64_t> interval_minus(std::int64_t a, std::int64_t b, std::int64_t n) {
  if (b >= a + n || b + n <= a) return {a, a + n};
  if (b > a) return {a, b};
  return {b + n, a + n};
}

GridOptions grid_like(const ElevationMap& map, int cells_per_side) {
  GridOptions g;
  g.cells_per_side = cells_per_side;
  g.cell_size_m = map.cell_size_m();
  for (std::size_t l = builtin_layers().size(); l < map.layer_count(); ++l) g.extra_layers.push_back(map.layer_spec(l));
  return g;
}

// Copies the cells of `rect` (inside both maps' windows) layer by layer.
template <class Rect>
void copy_cells(const ElevationMap& from, ElevationMap& to, const Rect& rect, const std::vector<std::size_t>& bytes) {
  for (std::size_t l = 0; l < bytes.size(); ++l) {
    const auto* src = static_cast<const unsigned char*>(from.layer_bytes(l));
    auto* dst = static_cast<unsigned char*>(to.layer_bytes(l));
    const std::size_t b = bytes[l];
    for (std::int64_t x = rect.min.x; x < rect.end.x; ++x) {
      for (std::int64_t y = rect.min.y; y < rect.end.y; ++y) {
        const CellIndex c{x, y};
        std::memcpy(dst + to.slot(c) * b, src + from.slot(c) * b, b);
      }
    }
  }
}

std::string describe_layers(const ElevationMap& map) {
  std::string s;
  for (std::size_t l = 0; l < map.layer_count(); ++l) {
    if (l) s += ", ";
    s += map.layer_spec(l).name + " (" + layer_type_name(map.layer_spec(l).type) + ")";
  }
  return s;
}

bool parse_tile_name(const std::string& name, TileIndex& out) {
  long long x = 0, y = 0;
  char tail = 0;
  if (std::sscanf(name.c_str(), "tile_%lld_%lld.sma%c", &x, &y, &tail) != 3 || tail != 'p') return false;
  if (tile_file_name({x, y}) != name) return false;
  out = {x, y};
  return true;
}

// What the manifest of an earlier run in `folder` says, against this
// run's tiles; empty when the folder has no manifest.
std::string earlier_global_map(const std::string& folder, int tile_cells, std::optional<double> cell_size_m) {
  std::ifstream in(fs::path(folder) / kGlobalMapManifest);
  if (!in) return {};
  const json manifest = json::parse(in, nullptr, false);
  const auto field = [&](const char* key) {
    return manifest.is_object() && manifest.contains(key) ? manifest[key].dump() : std::string("?");
  };
  std::ostringstream s;
  s << kGlobalMapManifest << ": tiles of " << field("tile_cells") << " cells of " << field("cell_size_m") << " m";
  if (cell_size_m) s << "; this run's: " << tile_cells << " cells of " << *cell_size_m << " m";
  return s.str();
}

}  // namespace

void check_global_map_folder(const GlobalMapOptions& options, std::optional<double> cell_size_m) {
  validate_global_map_options(options);
  if (options.folder.empty()) throw InputError("global map: no folder given");
  std::error_code ec;
  const fs::file_status status = fs::status(options.folder, ec);
  if (!fs::exists(status)) return;
  if (!fs::is_directory(status)) throw InputError("global map folder '" + options.folder + "' is a file, not a folder");
  fs::directory_iterator it(options.folder, ec);
  if (ec) throw InputError("global map folder '" + options.folder + "' cannot be read: " + ec.message());
  if (it == fs::directory_iterator()) return;
  const std::string why =
      "tiles are written only into a new or empty folder, so that no file this run did not create is ever replaced";
  const std::string earlier = earlier_global_map(options.folder, options.tile_cells, cell_size_m);
  if (!earlier.empty()) {
    throw InputError("global map folder '" + options.folder + "' already holds a global map (" + earlier + "); " +
                     why + ": give a new folder, or merge the old one with merge-tiles");
  }
  throw InputError("global map folder '" + options.folder + "' is not empty (it holds '" +
                   it->path().filename().string() + "'); " + why);
}

std::string tile_file_name(TileIndex t) {
  return "tile_" + std::to_string(t.x) + "_" + std::to_string(t.y) + ".smap";
}

TileStore::TileStore(const GlobalMapOptions& options, const ElevationMap& like, MapFileMetadata metadata)
    : options_(options),
      metadata_(std::move(metadata)),
      tile_grid_(grid_like(like, options.tile_cells)),
      window_cells_(like.cells_per_side()),
      reset_cell_(grid_like(like, 1)) {
  check_global_map_folder(options_, like.cell_size_m());
  std::error_code ec;
  if (!fs::exists(options_.folder, ec) && !fs::create_directories(options_.folder, ec) && ec) {
    throw InputError("global map folder '" + options_.folder + "' cannot be created: " + ec.message());
  }
  for (std::size_t l = 0; l < like.layer_count(); ++l) layer_bytes_.push_back(layer_type_bytes(like.layer_spec(l).type));
  cache_.resize(static_cast<std::size_t>(options_.cached_tiles));
  for (Cached& c : cache_) c.map = std::make_unique<ElevationMap>(tile_grid_);
  // Before any mapping: a folder that cannot take the manifest ends the run
  // here rather than hold back every tile.
  write_text_file(manifest_path(), manifest_text(), "global map manifest");
}

TileIndex TileStore::tile_of(CellIndex c) const {
  return stridemap::tile_of(c, options_.tile_cells);
}

std::string TileStore::tile_path(TileIndex t) const { return (fs::path(options_.folder) / tile_file_name(t)).string(); }

std::pair<TileStore::CellRect, TileStore::CellRect> TileStore::difference(CellIndex a, CellIndex b) const {
  const std::int64_t n = window_cells_;
  const auto [x0, x1] = interval_minus(a.x, b.x, n);
  const auto [y0, y1] = interval_minus(a.y, b.y, n);
  // Whole rows of `a` whose x is outside `b`, then the rest of the rows
  // both cover.
  CellRect rows{{x0, a.y}, {x1, a.y + n}};
  const std::int64_t kx0 = std::max(a.x, b.x), kx1 = std::min(a.x, b.x) + n;
  CellRect columns{{kx0, y0}, {kx1, y1}};
  return {rows, columns};
}

void TileStore::window_leaving(const ElevationMap& map, CellIndex new_min) {
  if (map.layer_count() != layer_bytes_.size() || map.cells_per_side() != window_cells_) {
    throw InputError("global map '" + options_.folder + "': the window's layers or size changed after the store was made");
  }
  const auto [rows, columns] = difference(map.min_cell(), new_min);
  if (!rows.empty()) save_rect(map, rows);
  if (!columns.empty()) save_rect(map, columns);
  write_tiles_left(new_min);
}

void TileStore::write_tiles_left(CellIndex new_min) {
  // A tile the new window does not reach cannot change until the window
  // comes back, so it goes to disk now: what a killed run loses is then
  // bounded by the tiles the window touches, however long it walked.
  // While writes fail the tiles wait in memory for flush() to try again,
  // rather than a doomed write on every move.
  if (failing_) return;
  const std::int64_t t = options_.tile_cells, n = window_cells_;
  for (Cached& c : cache_) {
    if (!c.used || !c.dirty) continue;
    if (!tile_meets(c.index, t, new_min, {new_min.x + n, new_min.y + n})) write(c);
  }
}

void TileStore::window_entered(ElevationMap& map, CellIndex old_min) {
  const auto [rows, columns] = difference(map.min_cell(), old_min);
  if (!rows.empty()) restore_rect(map, rows);
  if (!columns.empty()) restore_rect(map, columns);
}

void TileStore::flush(const ElevationMap& window) {
  const CellIndex lo = window.min_cell();
  save_rect(window, {lo, {lo.x + window_cells_, lo.y + window_cells_}});
  const std::size_t held = unsaved_.size();
  for (Cached& c : cache_) {
    if (c.used && c.dirty) write(c);
  }
  std::erase_if(unsaved_, [this](Cached& c) { return write(c); });
  if (manifest_dirty_) write_manifest();
  if (failing_ && unsaved() == 0 && !manifest_dirty_) {
    failing_ = false;
    notices_.push_back("global map: tiles are written again (" + std::to_string(held) +
                       " held in memory are on disk now)");
  }
}

std::size_t TileStore::unsaved() const {
  std::size_t n = unsaved_.size();
  for (const Cached& c : cache_) n += c.used && c.dirty && failing_;
  return n;
}

std::vector<std::string> TileStore::take_notices() {
  std::vector<std::string> out;
  out.swap(notices_);
  return out;
}

void TileStore::note_write_failure(const std::string& what) {
  ++stats_.write_failures;
  // Told once per outage, not once per try.
  if (!failing_) {
    notices_.push_back("global map: " + what +
                       "; tiles not written stay in memory and are written again at the next save");
  }
  failing_ = true;
}

// Calls f(tile, part) for each tile the rectangle meets, with the part of
// the rectangle inside it.
template <class F>
static void for_each_tile(std::int64_t t, CellIndex lo, CellIndex end, F&& f) {
  const TileIndex first = tile_of(lo, t), last = tile_of({end.x - 1, end.y - 1}, t);
  for (std::int64_t tx = first.x; tx <= last.x; ++tx) {
    for (std::int64_t ty = first.y; ty <= last.y; ++ty) {
      const TileIndex tile{tx, ty};
      const CellIndex tile_lo = tile_min_cell(tile, t), tile_end = tile_end_cell(tile, t);
      const CellIndex part_lo{std::max(lo.x, tile_lo.x), std::max(lo.y, tile_lo.y)};
      const CellIndex part_end{std::min(end.x, tile_end.x), std::min(end.y, tile_end.y)};
      f(tile, part_lo, part_end);
    }
  }
}

void TileStore::save_rect(const ElevationMap& map, const CellRect& rect) {
  for_each_tile(options_.tile_cells, rect.min, rect.end, [&](TileIndex t, CellIndex lo, CellIndex end) {
    const CellRect part{lo, end};
    // A tile is made only for cells that hold something: driving over
    // unseen ground leaves no files behind.
    const bool create = holds_data(map, part);
    Cached* c = tile(t, create);
    if (!c) return;
    copy_cells(map, *c->map, part, layer_bytes_);
    c->dirty = true;
    stats_.cells_saved += static_cast<std::size_t>((end.x - lo.x) * (end.y - lo.y));
  });
}

void TileStore::restore_rect(ElevationMap& map, const CellRect& rect) {
  for_each_tile(options_.tile_cells, rect.min, rect.end, [&](TileIndex t, CellIndex lo, CellIndex end) {
    Cached* c = tile(t, false);
    if (!c) return;
    copy_cells(*c->map, map, CellRect{lo, end}, layer_bytes_);
    stats_.cells_restored += static_cast<std::size_t>((end.x - lo.x) * (end.y - lo.y));
  });
}

bool TileStore::holds_data(const ElevationMap& map, const CellRect& rect) const {
  for (std::size_t l = 0; l < layer_bytes_.size(); ++l) {
    const auto* data = static_cast<const unsigned char*>(map.layer_bytes(l));
    const auto* reset = static_cast<const unsigned char*>(reset_cell_.layer_bytes(l));
    const std::size_t b = layer_bytes_[l];
    for (std::int64_t x = rect.min.x; x < rect.end.x; ++x) {
      for (std::int64_t y = rect.min.y; y < rect.end.y; ++y) {
        if (std::memcmp(data + map.slot({x, y}) * b, reset, b) != 0) return true;
      }
    }
  }
  return false;
}

TileStore::Cached* TileStore::tile(TileIndex index, bool create) {
  ++clock_;
  Cached* free_slot = nullptr;
  Cached* oldest = nullptr;
  for (Cached& c : cache_) {
    if (!c.used) {
      free_slot = &c;
    } else if (c.index == index) {
      c.last_use = clock_;
      return &c;
    } else if (!oldest || c.last_use < oldest->last_use) {
      oldest = &c;
    }
  }
  const auto held_back = [&] {
    return std::find_if(unsaved_.begin(), unsaved_.end(), [&](const Cached& c) { return c.index == index; });
  };
  const bool stored = on_disk_.count(index) != 0;
  if (!stored && !create && held_back() == unsaved_.end()) return nullptr;
  Cached* slot = free_slot ? free_slot : oldest;
  evict(*slot);
  bool dirty = false;
  if (const auto held = held_back(); held != unsaved_.end()) {
    std::swap(slot->map, held->map);  // newer than any file of it
    unsaved_.erase(held);
    dirty = true;
  } else {
    bool blank = !stored;
    if (stored) {
      try {
        read(index, *slot->map);
      } catch (const InputError& e) {
        set_aside(index, e.what());
        blank = true;
      }
    }
    if (blank) {
      slot->map->clear();
      slot->map->move_corner_to(tile_min_cell(index, options_.tile_cells));
    }
  }
  slot->index = index;
  slot->used = true;
  slot->dirty = dirty;
  slot->last_use = clock_;
  return slot;
}

void TileStore::evict(Cached& slot) {
  if (slot.used && slot.dirty && (failing_ || !write(slot))) {
    // Allocates, but only while the disk fails: losing the cells is worse.
    unsaved_.push_back(Cached{slot.index, std::move(slot.map), true, true, slot.last_use});
    slot.map = std::make_unique<ElevationMap>(tile_grid_);
  }
  slot.used = false;  // until it holds the new tile: a failed read leaves no half tile
}

void TileStore::set_aside(TileIndex index, const std::string& why) {
  ++stats_.tiles_set_aside;
  // No longer a tile of this run on disk: read again it would fail again.
  on_disk_.erase(index);
  stats_.tiles_on_disk = on_disk_.size();
  manifest_dirty_ = true;
  const std::string path = tile_path(index);
  std::error_code ec;
  if (!fs::exists(fs::symlink_status(path, ec))) {
    notices_.push_back("global map: " + why + "; its cells start unknown and are mapped anew");
    return;
  }
  // Never over an earlier damaged copy: each is kept for whoever looks into it.
  std::string aside = path + ".damaged";
  for (int k = 2; fs::exists(fs::symlink_status(aside, ec)); ++k) aside = path + ".damaged" + std::to_string(k);
  fs::rename(path, aside, ec);
  notices_.push_back("global map: " + why + "; " +
                     (ec ? "it could not be set aside (" + ec.message() + ")" : "set aside as " + aside) +
                     ", its cells start unknown and are mapped anew");
}

void TileStore::read(TileIndex index, ElevationMap& into) {
  const std::string path = tile_path(index);
  const MapFile file = load_map_file(path);
  const ElevationMap& m = file.map;
  const CellIndex corner = tile_min_cell(index, options_.tile_cells);
  const auto fail = [&](const std::string& what) {
    throw InputError(path + ": not a tile of this global map: " + what);
  };
  if (m.cells_per_side() != options_.tile_cells) {
    fail("it has " + std::to_string(m.cells_per_side()) + " cells a side, tiles have " +
         std::to_string(options_.tile_cells));
  }
  if (m.cell_size_m() != reset_cell_.cell_size_m()) {
    fail("its cells are " + std::to_string(m.cell_size_m()) + " m, the map's " +
         std::to_string(reset_cell_.cell_size_m()) + " m");
  }
  if (!(m.min_cell() == corner)) {
    fail("its corner cell is (" + std::to_string(m.min_cell().x) + ", " + std::to_string(m.min_cell().y) +
         "), its name says (" + std::to_string(corner.x) + ", " + std::to_string(corner.y) + ")");
  }
  bool same_layers = m.layer_count() == reset_cell_.layer_count();
  for (std::size_t l = 0; same_layers && l < m.layer_count(); ++l) {
    same_layers = m.layer_spec(l).name == reset_cell_.layer_spec(l).name &&
                  m.layer_spec(l).type == reset_cell_.layer_spec(l).type;
  }
  if (!same_layers) fail("its layers are " + describe_layers(m) + ", the map's " + describe_layers(reset_cell_));
  // Same size and corner: the same slots, so each layer copies whole.
  into.move_corner_to(corner);
  const std::size_t cells = static_cast<std::size_t>(options_.tile_cells) * static_cast<std::size_t>(options_.tile_cells);
  for (std::size_t l = 0; l < layer_bytes_.size(); ++l) {
    std::memcpy(into.layer_bytes(l), m.layer_bytes(l), cells * layer_bytes_[l]);
  }
  ++stats_.tiles_read;
}

bool TileStore::write(Cached& c) {
  const std::string path = tile_path(c.index);
  const bool ours = on_disk_.count(c.index) != 0;
  MapFileMetadata m = metadata_;
  m.created_by = "global map tile (" + std::to_string(c.index.x) + ", " + std::to_string(c.index.y) + ")" +
                 (metadata_.created_by.empty() ? "" : " of " + metadata_.created_by);
  try {
    std::error_code ec;
    if (!ours && fs::exists(fs::symlink_status(path, ec))) {
      throw InputError("'" + path + "' appeared during the run; it is not replaced, as this run did not create it");
    }
    save_map_file(path, *c.map, m);
  } catch (const InputError& e) {
    note_write_failure(e.what());
    return false;
  } catch (const std::system_error& e) {
    note_write_failure("writing '" + path + "' failed: " + e.what());
    return false;
  }
  c.dirty = false;
  ++stats_.tiles_written;
  if (!ours) {
    on_disk_.insert(c.index);
    stats_.tiles_on_disk = on_disk_.size();
    manifest_dirty_ = true;
    write_manifest();
  }
  return true;
}

std::string TileStore::manifest_path() const { return (fs::path(options_.folder) / kGlobalMapManifest).string(); }

std::string TileStore::manifest_text() const {
  json tiles = json::array();
  for (const TileIndex& t : on_disk_) tiles.push_back({t.x, t.y});
  const json manifest = {
      {"format", "stridemap global map"},
      {"version", 1},
      {"tile_cells", options_.tile_cells},
      {"cell_size_m", reset_cell_.cell_size_m()},
      {"tile_file", "tile_<x>_<y>.smap holds the cells [x * tile_cells, (x + 1) * tile_cells) x "
                    "[y * tile_cells, (y + 1) * tile_cells): a map file (docs/map_file.md)"},
      {"tiles", std::move(tiles)},
      {"tool_version", tool_version()}};
  return manifest.dump(2) + "\n";
}

bool TileStore::write_manifest() {
  try {
    write_text_file(manifest_path(), manifest_text(), "global map manifest");
  } catch (const InputError& e) {
    note_write_failure(e.what());
    return false;
  }
  manifest_dirty_ = false;
  return true;
}

MergedTiles merge_tiles(const std::string& folder) {
  const fs::path manifest_path = fs::path(folder) / kGlobalMapManifest;
  std::ifstream in(manifest_path);
  if (!in) throw InputError("'" + folder + "' is not a global map folder: it has no readable " + kGlobalMapManifest);
  json manifest;
  try {
    in >> manifest;
  } catch (const json::exception& e) {
    throw InputError(manifest_path.string() + ": not valid JSON (" + e.what() + ")");
  }
  const json* tile_cells = manifest.contains("tile_cells") ? &manifest["tile_cells"] : nullptr;
  if (manifest.value("format", "") != "stridemap global map" || !tile_cells || !tile_cells->is_number_integer() ||
      tile_cells->get<long long>() < 1 || tile_cells->get<long long>() > kMaxGridCellsPerSide) {
    throw InputError(manifest_path.string() + ": not a global map manifest (format or tile_cells missing or wrong)");
  }
  const std::int64_t t = tile_cells->get<std::int64_t>();
  std::vector<std::pair<TileIndex, fs::path>> tiles;
  for (const fs::directory_entry& e : fs::directory_iterator(folder)) {
    TileIndex index;
    if (parse_tile_name(e.path().filename().string(), index)) tiles.emplace_back(index, e.path());
  }
  std::sort(tiles.begin(), tiles.end());
  std::vector<std::string> holes;
  // Manifests of older versions list no tiles: then no tile can be missed.
  const json* listed = manifest.contains("tiles") ? &manifest["tiles"] : nullptr;
  if (listed && listed->is_array()) {
    for (const json& entry : *listed) {
      if (!entry.is_array() || entry.size() != 2 || !entry[0].is_number_integer() || !entry[1].is_number_integer()) {
        throw InputError(manifest_path.string() + ": tiles: expected pairs of whole numbers, got " + entry.dump());
      }
      const TileIndex index{entry[0].get<std::int64_t>(), entry[1].get<std::int64_t>()};
      const bool present = std::binary_search(tiles.begin(), tiles.end(), std::pair<TileIndex, fs::path>{index, {}},
                                              [](const auto& a, const auto& b) { return a.first < b.first; });
      if (!present) {
        holes.push_back((fs::path(folder) / tile_file_name(index)).string() + ": listed in " + kGlobalMapManifest +
                        " but missing");
      }
    }
  }
  if (tiles.empty()) throw InputError("global map folder '" + folder + "' holds no tiles");
  TileIndex lo = tiles.front().first, hi = lo;
  for (const auto& [index, path] : tiles) {
    lo = {std::min(lo.x, index.x), std::min(lo.y, index.y)};
    hi = {std::max(hi.x, index.x), std::max(hi.y, index.y)};
  }
  const std::int64_t span = std::max(hi.x - lo.x, hi.y - lo.y) + 1;
  if (span * t > kMaxGridCellsPerSide) {
    throw GridSizeError("global map '" + folder + "': its tiles span " + std::to_string(span * t) +
                        " cells a side, more than one map holds (" + std::to_string(kMaxGridCellsPerSide) + ")");
  }
  std::optional<ElevationMap> merged;
  std::string first_path;
  std::vector<std::size_t> bytes;
  for (const auto& [index, path] : tiles) {
    try {
      MapFile file = load_map_file(path.string());
      const ElevationMap& m = file.map;
      const CellIndex corner = tile_min_cell(index, t);
      if (m.cells_per_side() != t || !(m.min_cell() == corner)) {
        throw InputError(path.string() + ": not a tile of this global map (its size or corner does not fit its name)");
      }
      if (merged && (m.cell_size_m() != merged->cell_size_m() || describe_layers(m) != describe_layers(*merged))) {
        throw InputError(path.string() + ": its cell size or layers differ from those of " + first_path);
      }
      if (!merged) {
        merged.emplace(grid_like(m, static_cast<int>(span * t)));
        merged->move_corner_to(tile_min_cell(lo, t));
        for (std::size_t l = 0; l < m.layer_count(); ++l) bytes.push_back(layer_type_bytes(m.layer_spec(l).type));
        first_path = path.string();
      }
      struct {
        CellIndex min, end;
      } all{corner, tile_end_cell(index, t)};
      copy_cells(m, *merged, all, bytes);
    } catch (const InputError& e) {
      holes.push_back(e.what());
    }
  }
  if (!merged) {
    throw InputError("global map folder '" + folder + "': none of its " + std::to_string(tiles.size()) +
                     " tiles could be read (" + holes.front() + ")");
  }
  return {std::move(*merged), std::move(holes)};
}

}  // namespace stridemap::io
