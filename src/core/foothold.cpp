#include "stridemap/core/foothold.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <utility>

#include "foothold_cells.hpp"
#include "foothold_plane_fit.hpp"
#include "foothold_score.hpp"
#include "stridemap/core/error.hpp"

namespace stridemap {
namespace {

using foothold::kNaN;
using foothold::same_bits;

// Squared edge distances beyond this are computed, not looked up.
constexpr std::int64_t kEdgeTable = 1 << 16;
// Cells scored at once: enough to keep the lanes full, small beside a window.
constexpr std::size_t kScoreBatch = 256;

void require(bool ok, const char* field, double value, const char* rule) {
  if (!ok) {
    throw InputError(std::string("foothold options: ") + field + " must be " + rule + ", got " + std::to_string(value));
  }
}

bool finite_positive(double v) { return std::isfinite(v) && v > 0.0; }
bool finite_non_negative(double v) { return std::isfinite(v) && v >= 0.0; }

// The parts of `outer` outside `inner` (inner within outer), as up to four
// boxes: whole rows before and after inner's, then columns either side.
std::array<CellBox, 4> outside(const CellBox& outer, const CellBox& inner) {
  std::array<CellBox, 4> parts{};
  if (inner == outer) return parts;
  const CellBox& w = outer;
  const CellBox& s = inner;
  if (w.min.x < s.min.x) parts[0] = {w.min, {s.min.x - 1, w.max.y}};
  if (s.max.x < w.max.x) parts[1] = {{s.max.x + 1, w.min.y}, w.max};
  if (w.min.y < s.min.y) parts[2] = {{s.min.x, w.min.y}, {s.max.x, s.min.y - 1}};
  if (s.max.y < w.max.y) parts[3] = {{s.min.x, s.max.y + 1}, {s.max.x, w.max.y}};
  return parts;
}

}  // namespace

void validate_foothold_options(const FootholdOptions& o) {
  require(finite_positive(o.foot_radius_m), "foot_radius_m", o.foot_radius_m, "a finite radius > 0 m");
  require(std::isfinite(o.max_slope_deg) && o.max_slope_deg > 0.0 && o.max_slope_deg <= 90.0, "max_slope_deg",
          o.max_slope_deg, "an angle > 0 and <= 90 deg");
  require(finite_positive(o.max_step_m), "max_step_m", o.max_step_m, "a finite height > 0 m");
  require(finite_positive(o.max_roughness_m), "max_roughness_m", o.max_roughness_m, "a finite length > 0 m");
  require(finite_non_negative(o.edge_search_radius_m), "edge_search_radius_m", o.edge_search_radius_m,
          "a finite radius >= 0 m");
  require(finite_non_negative(o.edge_clearance_m), "edge_clearance_m", o.edge_clearance_m, "a finite length >= 0 m");
  require(finite_positive(o.full_certainty), "full_certainty", o.full_certainty, "a finite number > 0");
  require(std::isfinite(o.min_known_fraction) && o.min_known_fraction >= 0.0 && o.min_known_fraction <= 1.0,
          "min_known_fraction", o.min_known_fraction, "a fraction from 0 to 1");
  require(std::isfinite(o.safe_score) && o.safe_score >= 0.0 && o.safe_score <= 1.0, "safe_score", o.safe_score,
          "a score from 0 to 1");
}

std::array<LayerSpec, 5> foothold_layer_specs() {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  return {{
      {"slope_deg", LayerType::f32, nan, "deg", "slope of the plane fitted over the foot's footprint", true},
      {"roughness_m", LayerType::f32, nan, "m", "RMS residual of that plane fit", true},
      {"step_height_m", LayerType::f32, nan, "m", "max minus min elevation within the foot radius", true},
      {"edge_distance_m", LayerType::f32, nan, "m",
       "distance to the nearest cell whose step height exceeds max_step_m (capped at the search radius)", true},
      {"foothold_score", LayerType::f32, nan, "", "foothold quality in [0, 1] (docs/foothold.md)", true},
  }};
}

FootholdLayers::FootholdLayers(ElevationMap& map, const FootholdOptions& options) : options_(options) {
  validate_foothold_options(options_);
  for (const LayerSpec& spec : foothold_layer_specs()) {
    const std::optional<std::size_t> there = map.find_layer(spec.name);
    map.mark_derived(there ? *there : map.add_layer(spec));
  }
  slope_ = map.layer<float>("slope_deg");
  roughness_ = map.layer<float>("roughness_m");
  step_ = map.layer<float>("step_height_m");
  edge_distance_ = map.layer<float>("edge_distance_m");
  score_ = map.layer<float>("foothold_score");
  n_ = map.cells_per_side();
  cell_size_m_ = map.cell_size_m();
  stencil_ = FootholdStencil(options_.foot_radius_m, options_.edge_search_radius_m, options_.min_known_fraction,
                             cell_size_m_, n_);
  // The score's edge distance and factor per squared distance, the same
  // expressions as computed per cell (a table only up to a size; a larger
  // search radius computes beyond it).
  const std::int64_t none2 = stencil_.edge_cells * stencil_.edge_cells + 1;
  for (std::int64_t b = 0; b <= std::min<std::int64_t>(none2, kEdgeTable); ++b) {
    const double d = edge_distance_m_of(b, none2);
    edge_distance_of_.push_back(d);
    edge_factor_of_.push_back(edge_factor_of_distance(d));
  }
  changes_ = FootholdChanges(n_, static_cast<std::int32_t>(none2), options_.full_certainty);
  edges_ = FootholdEdgeSearch(n_);
  score_slots_.assign(kScoreBatch, 0);
  score_edge_factors_.assign(kScoreBatch, 0.0);
  padded_ = PaddedElevations(n_, stencil_.foot_cells);
}

double FootholdLayers::edge_distance_m_of(std::int64_t b2, std::int64_t none2) const {
  return b2 < none2 ? std::sqrt(static_cast<double>(b2)) * cell_size_m_ : options_.edge_search_radius_m;
}

double FootholdLayers::edge_factor_of_distance(double distance_m) const {
  return options_.edge_clearance_m > 0.0 ? std::min(1.0, distance_m / options_.edge_clearance_m) : 1.0;
}

void FootholdLayers::note(const ElevationMap& map, const ChangedRows& changed) { changes_.note(map, changed); }

void FootholdLayers::note(const ElevationMap& map, const CellBox& changed) { changes_.note(map, changed); }

void FootholdLayers::update(ElevationMap& map, const CellBox& changed) {
  note(map, changed);
  refresh(map);
}

void FootholdLayers::update(ElevationMap& map, const ChangedRows& changed) {
  note(map, changed);
  refresh(map);
}

void FootholdLayers::recompute_all(ElevationMap& map) {
  compute(map);
  changes_.pending.clear();
  changes_.window = changes_.stable = CellBox::window_of(map);
  changes_.computed = true;
}

void FootholdLayers::refresh(ElevationMap& map) {
  FootholdChanges& c = changes_;
  if (!c.computed) {
    recompute_all(map);
    return;
  }
  const CellBox window = CellBox::window_of(map);
  c.stable = c.stable.intersected(window);
  last_geometry_cells_ = last_score_cells_ = last_edge_cells_ = 0;
  if (c.pending.empty() && c.stable == c.window && c.window == window) return;
  if (c.stable.empty()) {  // the window jumped by a whole window or more
    recompute_all(map);
    return;
  }
  const CellIndex corner = window.min;
  const auto local = [&](const CellBox& b) {
    return LocalBox{b.min.x - corner.x, b.max.x - corner.x, b.min.y - corner.y, b.max.y - corner.y};
  };
  c.set_slots(map);
  std::fill(c.flips.begin(), c.flips.end(), RowSpan{n_, -1});
  // Cells of the last refresh's window outside every window since: they
  // left (and may have come back reset). First, as their slots may hold
  // cells that entered since.
  for (const CellBox& b : outside(c.window, c.stable)) {
    if (!b.empty()) c.see_left(stencil_, map, b, corner);
  }
  // Noted cells in every window since: where they differ from what the last
  // refresh saw. Noted cells outside stable are among those next.
  c.see_changes(stencil_, map, window);
  // Cells of the window outside stable entered it (or left and came back
  // reset): the last refresh saw them unknown (or they are among those that
  // left, above).
  for (const CellBox& b : outside(window, c.stable)) {
    if (!b.empty()) c.see_all(stencil_, map, local(b), true);
  }
  geometry_rows(map);
  // A score changes with its own cell's geometry, known-ness and certainty
  // (marked above) and with the edge distance, which changes only within
  // the search radius of a cell that became or stopped being an edge: one
  // whose step crossed max_step_m, or one that left (a cell outside the
  // window stands in as its nearest window cell, which is no farther from
  // any window cell). A cell that became known since it entered gets its
  // first.
  grow_rows(c.flips, edges_.edge_rows, stencil_.edge_widths);
  search_or_raise_edges(edges_, c, stencil_);
  for (std::size_t x = 0; x < edges_.edge_rows.size(); ++x) {
    RowSpan& u = c.unseen_edge_rows[x];
    if (u.lo > u.hi) continue;
    RowSpan& e = edges_.edge_rows[x];
    e.lo = std::min(e.lo, u.lo);
    e.hi = std::max(e.hi, u.hi);
    u = RowSpan{n_, -1};
  }
  last_edge_cells_ =
      search_edge_distances(edges_, c, stencil_, map.data(step_), static_cast<float>(options_.max_step_m), false);
  raise_edges(c, stencil_);
  score_rows(map);
  c.pending.clear();
  c.window = c.stable = window;
}

void FootholdLayers::compute(ElevationMap& map) {
  if (compute_without_known_cells(map)) return;
  FootholdChanges& c = changes_;
  c.set_slots(map);
  c.see_all(stencil_, map, {0, n_ - 1, 0, n_ - 1}, false);
  for (int i = 0; i < n_; ++i) c.mark_geometry_span(i, 0, n_ - 1);
  std::fill(c.geometry_rows.begin(), c.geometry_rows.end(), RowSpan{0, n_ - 1});
  std::fill(c.flips.begin(), c.flips.end(), RowSpan{n_, -1});
  geometry_rows(map);
  c.raised.clear();  // every distance is searched for
  std::fill(edges_.edge_rows.begin(), edges_.edge_rows.end(), RowSpan{0, n_ - 1});
  last_edge_cells_ =
      search_edge_distances(edges_, c, stencil_, map.data(step_), static_cast<float>(options_.max_step_m), true);
  for (int i = 0; i < n_; ++i) {
    FootholdChanges::set_bits(c.score_mark.data() + static_cast<std::size_t>(i) * c.mark_words, 0,
                              static_cast<std::size_t>(n_ - 1));
  }
  std::fill(c.score_rows.begin(), c.score_rows.end(), RowSpan{0, n_ - 1});
  score_rows(map);
}

// A map without a known cell (a new pipeline's, or one cleared) has NaN in
// every layer and no edge anywhere: written here as compute()'s full pass
// leaves them, marks, counts and edge distances included, for a small part
// of its cost. False, with nothing changed, when a cell is known.
bool FootholdLayers::compute_without_known_cells(ElevationMap& map) {
  const float* elevation = map.elevation_data();
  const std::uint8_t* state = map.state_data();
  const std::size_t cells = static_cast<std::size_t>(n_) * static_cast<std::size_t>(n_);
  for (std::size_t s = 0; s < cells; ++s) {
    if (foothold::known(elevation, state, s)) return false;
  }
  FootholdChanges& c = changes_;
  c.set_slots(map);
  std::fill(c.seen_elevation.begin(), c.seen_elevation.end(), kNaN);
  std::copy_n(map.certainty_data(), cells, c.seen_certainty.begin());
  std::fill(c.seen_edge2.begin(), c.seen_edge2.end(), static_cast<std::int32_t>(stencil_.edge_cells * stencil_.edge_cells + 1));
  for (const LayerId<float> layer : {slope_, roughness_, step_, edge_distance_, score_}) {
    std::fill_n(map.data(layer), cells, kNaN);
  }
  std::fill(c.geometry_mark.begin(), c.geometry_mark.end(), std::uint64_t{0});
  std::fill(c.score_mark.begin(), c.score_mark.end(), std::uint64_t{0});
  std::fill(c.geometry_rows.begin(), c.geometry_rows.end(), RowSpan{n_, -1});
  std::fill(c.score_rows.begin(), c.score_rows.end(), RowSpan{n_, -1});
  c.raised.clear();
  last_geometry_cells_ = last_score_cells_ = last_edge_cells_ = cells;
  return true;
}

// Redoes the marked cells' geometry (clearing the marks and the rows'
// hulls); marks the score of a cell whose geometry changed and notes the
// cells whose step crossed max_step_m.
void FootholdLayers::geometry_rows(ElevationMap& map) {
  FootholdChanges& c = changes_;
  const foothold::WindowSlots slots(map);
  const float* elevation = map.elevation_data();
  const std::uint8_t* state = map.state_data();
  const foothold::GeometryLayers out{map.data(slope_), map.data(roughness_), map.data(step_)};
  float* slope = out.slope_deg;
  float* roughness = out.roughness_m;
  float* step = out.step_height_m;
  std::size_t cells = 0;
  const auto max_step = static_cast<float>(options_.max_step_m);
  const bool fast = stencil_.footprint.size() <= foothold::kKept;
  c.raised.clear();
  const std::size_t* cols = c.col_slot.data();
  foothold::LaneFits lanes;
  // Known-ness and elevation from what this refresh saw (the map's: see_changes()).
  if (fast) padded_.copy(c.geometry_rows, c.seen_elevation, c.row_slot, c.col_slot);
  // In locals, as in score_rows(): the layers' float stores may alias these.
  const float* padded_values = padded_.values.data();
  const std::ptrdiff_t padded_margin = padded_.margin, padded_stride = padded_.stride;
  std::uint64_t* score_marks = c.score_mark.data();
  const std::size_t mark_words = c.mark_words;
  // A new fit of cell (i, j), already written to slot t: its score is
  // redone if it changed, and it may have become or stopped being an edge.
  const auto fitted = [&](int i, int j, std::size_t t, float old_slope, float old_roughness, float old_step) {
    if (!same_bits(old_slope, slope[t]) || !same_bits(old_roughness, roughness[t]) || !same_bits(old_step, step[t])) {
      const auto column = static_cast<std::size_t>(j);
      score_marks[static_cast<std::size_t>(i) * mark_words + column / 64] |= std::uint64_t{1} << (column % 64);
    }
    const bool edge = step[t] > max_step;
    if (edge && !(old_step > max_step)) {
      c.raised.push_back(static_cast<std::int32_t>(i * n_ + j));
    } else if (!edge && old_step > max_step) {
      RowSpan& flip = c.flips[static_cast<std::size_t>(i)];
      flip.lo = std::min(flip.lo, j);
      flip.hi = std::max(flip.hi, j);
    }
  };
  const auto slot_of = [&](int i, int j) { return c.row_slot[static_cast<std::size_t>(i)] + cols[j]; };
  // A marked cell with its storage slot and its entry in padded_, both
  // found once, when it is marked.
  struct Member {
    int i, j;
    std::size_t slot;
    const float* entry;
  };
  const auto store = [&](const Member& m, float new_slope, float new_roughness, float new_step) {
    ++cells;
    const std::size_t t = m.slot;
    const float old_slope = slope[t], old_roughness = roughness[t], old_step = step[t];
    slope[t] = new_slope;
    roughness[t] = new_roughness;
    step[t] = new_step;
    fitted(m.i, m.j, t, old_slope, old_roughness, old_step);
  };
  // The marked cells of known elevation, kLanes at a time whether
  // neighbours or not, rows included; a cell of unknown elevation has no fit.
  Member group[foothold::kLanes];
  int filled = 0;
  // Always inline (GCC's own choice varies with the code around it): out
  // of line, every captured variable is read through the closure.
  const auto fit_group = [&]() __attribute__((always_inline)) {
    const unsigned wanted = (1u << filled) - 1u;
    const Member& first = group[0];
    const Member& last = group[foothold::kLanes - 1];
    if (filled == foothold::kLanes && last.i == first.i && last.j - first.j == foothold::kLanes - 1) {
      foothold::fit_footprint_lanes(stencil_, inverses_, first.entry, padded_.stride, wanted, lanes);
    } else {
      foothold::LaneCentres centres;
      for (int l = 0; l < foothold::kLanes; ++l) centres.entry[l] = group[l < filled ? l : 0].entry;
      foothold::fit_footprint_cells(stencil_, inverses_, centres, padded_.stride, wanted, lanes);
    }
    for (int l = 0; l < filled; ++l) store(group[l], lanes.slope_deg[l], lanes.roughness_m[l], lanes.step_height_m[l]);
    filled = 0;
  };
  // One marked cell: fitted in a lane group, stored NaN, or (a footprint
  // too large for the lanes) fitted alone.
  const auto redo = [&](int i, int j, std::size_t t) {
    if (!fast) {
      const float old_slope = slope[t], old_roughness = roughness[t], old_step = step[t];
      ++cells;
      foothold::fit_footprint(stencil_, slots, elevation, state, {slots.corner.x + i, slots.corner.y + j}, out);
      fitted(i, j, t, old_slope, old_roughness, old_step);
      return;
    }
    const float* entry = padded_values + (i + padded_margin) * padded_stride + (j + padded_margin);
    if (std::isnan(*entry)) {
      // Most such cells were unknown at the last refresh too: nothing to store.
      if (same_bits(slope[t], kNaN) && same_bits(roughness[t], kNaN) && same_bits(step[t], kNaN)) {
        ++cells;
      } else {
        store(Member{i, j, t, entry}, kNaN, kNaN, kNaN);
      }
    } else {
      group[filled++] = Member{i, j, t, entry};
      if (filled == foothold::kLanes) fit_group();
    }
  };
  for (int i = 0; i < n_; ++i) {
    RowSpan& s = c.geometry_rows[static_cast<std::size_t>(i)];
    if (s.lo > s.hi) continue;
    // A score this row's fits mark lies within the row's hull too.
    c.widen_scores(i, s.lo, s.hi);
    // The row's marks lie within its hull: only the hull's words are read,
    // each cleared as it is.
    std::uint64_t* words = c.geometry_mark.data() + static_cast<std::size_t>(i) * c.mark_words;
    const auto last = static_cast<std::size_t>(s.hi) / 64;
    for (auto w = static_cast<std::size_t>(s.lo) / 64; w <= last; ++w) {
      std::uint64_t marked = std::exchange(words[w], 0);
      if (marked == 0) continue;
      const auto word_start = static_cast<int>(w * 64);
      const std::size_t start = slot_of(i, word_start);
      if (c.word_in_one_run(start)) {
        for (; marked != 0; marked &= marked - 1) {
          const int b = std::countr_zero(marked);
          redo(i, word_start + b, start + static_cast<std::size_t>(b));
        }
      } else {
        for (; marked != 0; marked &= marked - 1) {
          const int j = word_start + std::countr_zero(marked);
          redo(i, j, slot_of(i, j));
        }
      }
    }
    s = RowSpan{n_, -1};
  }
  if (filled != 0) fit_group();
  last_geometry_cells_ = cells;
}

// Edge distance and score of the marked cells (clearing the marks and the
// rows' hulls); the scores of the cells that have one in batches.
void FootholdLayers::score_rows(ElevationMap& map) {
  const float* certainty = map.certainty_data();
  const float* step = map.data(step_);
  const float* slope = map.data(slope_);
  const float* roughness = map.data(roughness_);
  float* edge_distance = map.data(edge_distance_);
  float* score = map.data(score_);
  const std::int64_t none2 = stencil_.edge_cells * stencil_.edge_cells + 1;
  std::size_t cells = 0, scored = 0;
  // In locals: the layers are written through float pointers, which could
  // alias the vectors' own pointers and sizes, reloaded a cell each otherwise.
  const double* distance_of = edge_distance_of_.data();
  const double* factor_of = edge_factor_of_.data();
  const auto tabled_below = static_cast<std::int64_t>(edge_distance_of_.size());
  std::size_t* slots = score_slots_.data();
  double* factors = score_edge_factors_.data();
  const auto score_batch = [&] {
    const foothold::ScoreCells batch{slots, factors, scored, slope, step, roughness, certainty, options_.max_slope_deg,
                                     options_.max_step_m, options_.max_roughness_m, options_.full_certainty};
    foothold::score_cells(batch, score);
    scored = 0;
  };
  for (int x = 0; x < n_; ++x) {
    RowSpan& e = changes_.score_rows[static_cast<std::size_t>(x)];
    if (e.lo > e.hi) continue;
    std::uint64_t* words = changes_.score_mark.data() + static_cast<std::size_t>(x) * changes_.mark_words;
    const std::size_t row = changes_.row_slot[static_cast<std::size_t>(x)];
    // One marked cell, at storage slot s.
    const auto score_cell = [&](std::size_t s) {
      ++cells;
      if (std::isnan(changes_.seen_elevation[s])) {
        edge_distance[s] = score[s] = kNaN;
        return;
      }
      const std::int64_t b = changes_.seen_edge2[s];
      const bool tabled = b < tabled_below;
      const double distance_m = tabled ? distance_of[static_cast<std::size_t>(b)] : edge_distance_m_of(b, none2);
      edge_distance[s] = static_cast<float>(distance_m);
      if (std::isnan(slope[s]) || std::isnan(step[s]) || std::isnan(roughness[s])) {
        score[s] = kNaN;
        return;
      }
      slots[scored] = s;
      factors[scored++] = tabled ? factor_of[static_cast<std::size_t>(b)] : edge_factor_of_distance(distance_m);
      if (scored == kScoreBatch) score_batch();
    };
    const auto last = static_cast<std::size_t>(e.hi) / 64;
    for (auto w = static_cast<std::size_t>(e.lo) / 64; w <= last; ++w) {
      std::uint64_t marked = std::exchange(words[w], 0);
      if (marked == 0) continue;
      const std::size_t start = row + changes_.col_slot[w * 64];
      if (changes_.word_in_one_run(start)) {
        for (; marked != 0; marked &= marked - 1) score_cell(start + static_cast<std::size_t>(std::countr_zero(marked)));
      } else {
        for (; marked != 0; marked &= marked - 1) {
          score_cell(row + changes_.col_slot[w * 64 + static_cast<std::size_t>(std::countr_zero(marked))]);
        }
      }
    }
    e = RowSpan{n_, -1};
  }
  last_score_cells_ = cells;
  score_batch();
}

}  // namespace stridemap
