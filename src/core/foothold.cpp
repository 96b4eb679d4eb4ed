#include "stridemap/core/foothold.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <limits>
#include <numbers>
#include <span>
#include <string>

#include <Eigen/Dense>

#include "stridemap/core/error.hpp"

namespace stridemap {
namespace {

constexpr std::size_t kKept = 64;  // footprints up to this size keep their cells for the residuals
// Squared edge distances beyond this are computed, not looked up.
constexpr std::int64_t kEdgeTable = 1 << 16;
// seen_edge2_ of a cell that entered the window and is not yet known.
constexpr std::int32_t kEdgeUnknown = -1;
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

void require(bool ok, const char* field, double value, const char* rule) {
  if (!ok) {
    throw InputError(std::string("foothold options: ") + field + " must be " + rule + ", got " + std::to_string(value));
  }
}

bool finite_positive(double v) { return std::isfinite(v) && v > 0.0; }
bool finite_non_negative(double v) { return std::isfinite(v) && v >= 0.0; }

}  // namespace

// Slots of the window addressed by global index, without a modulo per
// cell: the storage row of local row i is (corner row + i) wrapped once.
struct FootholdLayers::LocalSlots {
  explicit LocalSlots(const ElevationMap& map)
      : n(map.cells_per_side()),
        corner(map.min_cell()),
        row0(static_cast<std::int64_t>(map.slot(map.min_cell()) / static_cast<std::size_t>(n))),
        col0(static_cast<std::int64_t>(map.slot(map.min_cell()) % static_cast<std::size_t>(n))) {}
  bool inside(CellIndex c) const { return c.x >= corner.x && c.y >= corner.y && c.x < corner.x + n && c.y < corner.y + n; }
  std::size_t of(CellIndex c) const {
    std::int64_t i = c.x - corner.x + row0, j = c.y - corner.y + col0;
    if (i >= n) i -= n;
    if (j >= n) j -= n;
    return static_cast<std::size_t>(i * n + j);
  }
  std::int64_t n;
  CellIndex corner;
  std::int64_t row0, col0;
};

namespace {

bool known(const float* elevation, const std::uint8_t* state, std::size_t s) {
  return state[s] != static_cast<std::uint8_t>(CellState::unknown) && std::isfinite(elevation[s]);
}

double ramp_down(double value, double limit) {
  if (!(limit > 0.0)) return value > 0.0 ? 0.0 : 1.0;
  return std::clamp(1.0 - value / limit, 0.0, 1.0);
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
    if (!map.find_layer(spec.name)) map.add_layer(spec);
  }
  slope_ = map.layer<float>("slope_deg");
  roughness_ = map.layer<float>("roughness_m");
  step_ = map.layer<float>("step_height_m");
  edge_distance_ = map.layer<float>("edge_distance_m");
  score_ = map.layer<float>("foothold_score");
  n_ = map.cells_per_side();
  cell_size_m_ = map.cell_size_m();
  // A relative epsilon keeps a radius that is a whole number of cells from
  // losing its outermost ring to rounding (0.03 / 0.01 = 2.9999...).
  const double foot_cells = options_.foot_radius_m / cell_size_m_ * (1.0 + 1e-9);
  foot_cells_ = static_cast<std::int64_t>(std::floor(foot_cells));
  edge_cells_ = static_cast<std::int64_t>(std::floor(options_.edge_search_radius_m / cell_size_m_ * (1.0 + 1e-9)));
  edge_cells_ = std::min<std::int64_t>(edge_cells_, n_);
  for (std::int64_t dx = -foot_cells_; dx <= foot_cells_; ++dx) {
    for (std::int64_t dy = -foot_cells_; dy <= foot_cells_; ++dy) {
      if (static_cast<double>(dx * dx + dy * dy) <= foot_cells * foot_cells) {
        footprint_.push_back({dx, dy});
        foot_x_m_.push_back(static_cast<double>(dx) * cell_size_m_);
        foot_y_m_.push_back(static_cast<double>(dy) * cell_size_m_);
        foot_dx_.push_back(static_cast<double>(dx));
        foot_dy_.push_back(static_cast<double>(dy));
      }
    }
  }
  min_known_ = std::max<std::size_t>(
      3, static_cast<std::size_t>(std::ceil(options_.min_known_fraction * static_cast<double>(footprint_.size()))));
  min_known_ = std::min(min_known_, std::max<std::size_t>(footprint_.size(), 3));
  Eigen::Matrix3d full = Eigen::Matrix3d::Zero();
  for (const CellIndex& o : footprint_) {
    const Eigen::Vector3d v(1.0, static_cast<double>(o.x) * cell_size_m_, static_cast<double>(o.y) * cell_size_m_);
    full.noalias() += v * v.transpose();
  }
  full_inverse_ = Eigen::Matrix3d::Zero();
  if (footprint_.size() >= 3) full_inverse_ = full.inverse();
  // The same predicates as the footprint's and the edge search's.
  for (std::int64_t dx = -foot_cells_; dx <= foot_cells_; ++dx) {
    int w = 0;
    while (w + 1 <= foot_cells_ && static_cast<double>(dx * dx + (w + 1) * (w + 1)) <= foot_cells * foot_cells) ++w;
    foot_widths_.push_back(static_cast<double>(dx * dx) <= foot_cells * foot_cells ? w : -1);
  }
  for (std::int64_t dx = -edge_cells_; dx <= edge_cells_; ++dx) {
    int w = 0;
    while (w + 1 <= edge_cells_ && dx * dx + (w + 1) * (w + 1) <= edge_cells_ * edge_cells_) ++w;
    edge_widths_.push_back(w);
  }
  // The score's edge distance and factor per squared distance, the same
  // expressions as computed per cell (a table only up to a size; a larger
  // search radius computes beyond it).
  const std::int64_t none2 = edge_cells_ * edge_cells_ + 1;
  for (std::int64_t b = 0; b <= std::min<std::int64_t>(none2, kEdgeTable); ++b) {
    const double d = edge_distance_m_of(b, none2);
    edge_distance_of_.push_back(d);
    edge_factor_of_.push_back(edge_factor_of_distance(d));
  }
  const auto n = static_cast<std::size_t>(n_);
  pending_.resize(n_);
  seen_elevation_.assign(n * n, kNaN);
  seen_certainty_.assign(n * n, 0.0f);
  seen_edge2_.assign(n * n, static_cast<std::int32_t>(none2));
  row_slot_.assign(n, 0);
  col_slot_.assign(n, 0);
  geometry_mark_.assign(n * n, 0);
  score_mark_.assign(n * n, 0);
  for (std::vector<Span>* rows :
       {&geometry_rows_, &score_rows_, &flips_, &edge_rows_, &unseen_edge_rows_, &distance_rows_}) {
    rows->assign(n, Span{n_, -1});
  }
  distance2_.assign(n * n, 0);
  best2_.assign(n, 0);
  raised_.reserve(n * n);  // a cell is raised at most once a refresh
  merged_.assign(n, Span{n_, -1});
  merged_rows_.assign(n, Span{n_, -1});
  for (const int w : edge_widths_) edge_disc_cells_ += static_cast<std::size_t>(2 * w + 1);
}

double FootholdLayers::edge_distance_m_of(std::int64_t b2, std::int64_t none2) const {
  return b2 < none2 ? std::sqrt(static_cast<double>(b2)) * cell_size_m_ : options_.edge_search_radius_m;
}

double FootholdLayers::edge_factor_of_distance(double distance_m) const {
  return options_.edge_clearance_m > 0.0 ? std::min(1.0, distance_m / options_.edge_clearance_m) : 1.0;
}

void FootholdLayers::note(const ElevationMap& map, const ChangedRows& changed) {
  if (!computed_) return;  // the first refresh computes everything
  stable_ = stable_.intersected(CellBox::window_of(map));
  pending_.add(changed);
}

void FootholdLayers::note(const ElevationMap& map, const CellBox& changed) {
  if (!computed_) return;
  stable_ = stable_.intersected(CellBox::window_of(map));
  pending_.add(changed);
}

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
  pending_.clear();
  window_ = stable_ = CellBox::window_of(map);
  computed_ = true;
}

void FootholdLayers::set_slots(const ElevationMap& map) {
  const auto n = static_cast<std::size_t>(n_);
  const std::size_t corner = map.slot(map.min_cell());
  const std::size_t row0 = corner / n, col0 = corner % n;
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t r = row0 + i;
    row_slot_[i] = (r >= n ? r - n : r) * n;
    const std::size_t c = col0 + i;
    col_slot_[i] = c >= n ? c - n : c;
  }
}

// Marks every window cell whose footprint holds a cell of `b`: the box
// grown by the footprint's disc, row by row.
void FootholdLayers::mark_geometry(const LocalBox& b) {
  const std::int64_t f = foot_cells_, n = n_;
  const std::int64_t x0 = std::max<std::int64_t>(b.i0 - f, 0), x1 = std::min<std::int64_t>(b.i1 + f, n - 1);
  for (std::int64_t x = x0; x <= x1; ++x) {
    const std::int64_t dx = x < b.i0 ? b.i0 - x : (x > b.i1 ? x - b.i1 : 0);
    const int w = foot_widths_[static_cast<std::size_t>(dx + f)];
    if (w < 0) continue;
    const int lo = static_cast<int>(std::max<std::int64_t>(b.j0 - w, 0));
    const int hi = static_cast<int>(std::min<std::int64_t>(b.j1 + w, n - 1));
    if (lo > hi) continue;
    std::fill_n(geometry_mark_.data() + x * n + lo, hi - lo + 1, std::uint8_t{1});
    Span& r = geometry_rows_[static_cast<std::size_t>(x)];
    r.lo = std::min(r.lo, lo);
    r.hi = std::max(r.hi, hi);
  }
}

void FootholdLayers::mark_edge(int i, int j) {
  Span& r = unseen_edge_rows_[static_cast<std::size_t>(i)];
  r.lo = std::min(r.lo, j);
  r.hi = std::max(r.hi, j);
}

// The cells of `b` (global, of the last refresh's window) that left every
// window since: a neighbour's footprint lost the known ones, and the edge
// distances within the search radius of one that was an edge may grow.
void FootholdLayers::see_left(const ElevationMap& map, const CellBox& b, CellIndex corner) {
  const auto clamp = [&](std::int64_t v) { return static_cast<int>(std::clamp<std::int64_t>(v, 0, n_ - 1)); };
  for (std::int64_t x = b.min.x; x <= b.max.x; ++x) {
    const std::int64_t i = x - corner.x;
    if (i < -foot_cells_ - edge_cells_ || i > n_ - 1 + foot_cells_ + edge_cells_) continue;  // reaches no window cell
    bool in_run = false;
    std::int64_t run = 0;
    for (std::int64_t y = b.min.y; y <= b.max.y + 1; ++y) {
      bool was_known = false;
      if (y <= b.max.y) {
        const std::size_t s = map.slot({x, y});
        was_known = !std::isnan(seen_elevation_[s]);
        if (seen_edge2_[s] == 0) {  // it was an edge
          Span& f = flips_[static_cast<std::size_t>(clamp(i))];
          f.lo = std::min(f.lo, clamp(y - corner.y));
          f.hi = std::max(f.hi, clamp(y - corner.y));
        }
      }
      if (was_known && !in_run) {
        run = y;
        in_run = true;
      } else if (!was_known && in_run) {
        mark_geometry({i, i, run - corner.y, y - 1 - corner.y});
        in_run = false;
      }
    }
  }
}

void FootholdLayers::mark_score(int i, int j) {
  score_mark_[static_cast<std::size_t>(i) * static_cast<std::size_t>(n_) + static_cast<std::size_t>(j)] = 1;
  Span& r = score_rows_[static_cast<std::size_t>(i)];
  r.lo = std::min(r.lo, j);
  r.hi = std::max(r.hi, j);
}

namespace {

float known_elevation(const float* elevation, const std::uint8_t* state, std::size_t s) {
  return known(elevation, state, s) ? elevation[s] : kNaN;
}

bool same_bits(float a, float b) { return std::bit_cast<std::uint32_t>(a) == std::bit_cast<std::uint32_t>(b); }
bool same_bits(double a, double b) { return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b); }

}  // namespace

double FootholdLayers::certainty_factor(float certainty) const {
  return std::clamp(static_cast<double>(certainty) / options_.full_certainty, 0.0, 1.0);
}

// The noted cells in every window since the last refresh: compared with
// what that refresh saw. A changed elevation or known-ness redoes the plane
// fits around the cell; a changed certainty factor, its score only.
void FootholdLayers::see_changes(const ElevationMap& map, const CellBox& window) {
  if (pending_.empty()) return;
  const float* elevation = map.elevation_data();
  const std::uint8_t* state = map.state_data();
  const float* certainty = map.certainty_data();
  const CellIndex corner = window.min;
  const CellBox rows = pending_.bounds().intersected(stable_);
  std::int64_t lo = 0, hi = 0;
  for (std::int64_t x = rows.min.x; !rows.empty() && x <= rows.max.x; ++x) {
    if (!pending_.span(x, lo, hi)) continue;
    lo = std::max(lo, stable_.min.y);
    hi = std::min(hi, stable_.max.y);
    const auto i = static_cast<int>(x - corner.x);
    const std::size_t row = row_slot_[static_cast<std::size_t>(i)];
    // Runs of consecutive changed cells are marked as one box.
    std::int64_t run = 0;
    bool in_run = false;
    for (std::int64_t y = lo; y <= hi + 1; ++y) {
      bool changed = false;
      if (y <= hi) {
        const auto j = static_cast<int>(y - corner.y);
        const std::size_t s = row + col_slot_[static_cast<std::size_t>(j)];
        const float now = known_elevation(elevation, state, s);
        const float before = seen_elevation_[s];
        if (!same_bits(now, before)) {
          changed = true;
          seen_elevation_[s] = now;
          // The edge distance is NaN exactly where the cell is unknown; a
          // cell that entered the window unknown has none to show yet.
          if (std::isnan(now) != std::isnan(before)) mark_score(i, j);
          if (seen_edge2_[s] == kEdgeUnknown && !std::isnan(now)) mark_edge(i, j);
        }
        if (!same_bits(certainty_factor(certainty[s]), certainty_factor(seen_certainty_[s]))) mark_score(i, j);
        seen_certainty_[s] = certainty[s];
      }
      if (changed && !in_run) {
        run = y;
        in_run = true;
      } else if (!changed && in_run) {
        mark_geometry({i, i, run - corner.y, y - 1 - corner.y});
        in_run = false;
      }
    }
  }
}

// Every cell of `b` (window-local, within the window): seen as it is now.
// With `mark`, a known one redoes the plane fits around it and its score
// (cells that entered the window were unknown to the last refresh).
void FootholdLayers::see_all(const ElevationMap& map, const LocalBox& b, bool mark) {
  const float* elevation = map.elevation_data();
  const std::uint8_t* state = map.state_data();
  const float* certainty = map.certainty_data();
  for (std::int64_t i = b.i0; i <= b.i1; ++i) {
    const std::size_t row = row_slot_[static_cast<std::size_t>(i)];
    for (std::int64_t j = b.j0; j <= b.j1; ++j) {
      const std::size_t s = row + col_slot_[static_cast<std::size_t>(j)];
      seen_elevation_[s] = known_elevation(elevation, state, s);
      seen_certainty_[s] = certainty[s];
      if (!mark) continue;
      // Its edge distance is searched for when it is known (below or later).
      seen_edge2_[s] = kEdgeUnknown;
      if (!std::isnan(seen_elevation_[s])) {
        mark_geometry({i, i, j, j});
        mark_score(static_cast<int>(i), static_cast<int>(j));
        mark_edge(static_cast<int>(i), static_cast<int>(j));
      }
    }
  }
}

// to[x] covers from[x + dx] widened by widths[dx + r] for |dx| <= r (the
// rows' hulls: a bound of the disc around every cell of `from`), for the
// window's rows.
void FootholdLayers::grow(const std::vector<Span>& from, std::vector<Span>& to, const std::vector<int>& widths) {
  const int r = static_cast<int>(widths.size() / 2);
  std::fill(to.begin(), to.end(), Span{n_, -1});
  for (int x = 0; x < static_cast<int>(from.size()); ++x) {
    const Span s = from[static_cast<std::size_t>(x)];
    if (s.lo > s.hi) continue;
    for (int dx = std::max(-r, -x); dx <= r && x + dx < n_; ++dx) {
      const int w = widths[static_cast<std::size_t>(dx + r)];
      if (w < 0) continue;
      Span& t = to[static_cast<std::size_t>(x + dx)];
      t.lo = std::min(t.lo, std::max(s.lo - w, 0));
      t.hi = std::max(t.hi, std::min(s.hi + w, n_ - 1));
    }
  }
}

namespace {

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

void FootholdLayers::refresh(ElevationMap& map) {
  if (!computed_) {
    recompute_all(map);
    return;
  }
  const CellBox window = CellBox::window_of(map);
  stable_ = stable_.intersected(window);
  last_geometry_cells_ = last_score_cells_ = last_edge_cells_ = 0;
  if (pending_.empty() && stable_ == window_ && window_ == window) return;
  if (stable_.empty()) {  // the window jumped by a whole window or more
    recompute_all(map);
    return;
  }
  const CellIndex corner = window.min;
  const auto local = [&](const CellBox& b) {
    return LocalBox{b.min.x - corner.x, b.max.x - corner.x, b.min.y - corner.y, b.max.y - corner.y};
  };
  set_slots(map);
  std::fill(flips_.begin(), flips_.end(), Span{n_, -1});
  // Cells of the last refresh's window outside every window since: they
  // left (and may have come back reset). First, as their slots may hold
  // cells that entered since.
  const std::array<CellBox, 4> left = outside(window_, stable_);
  for (const CellBox& b : left) {
    if (!b.empty()) see_left(map, b, corner);
  }
  // Noted cells in every window since: where they differ from what the last
  // refresh saw. Noted cells outside stable_ are among those next.
  see_changes(map, window);
  // Cells of the window outside stable_ entered it (or left and came back
  // reset): the last refresh saw them unknown (or they are among those that
  // left, above).
  const std::array<CellBox, 4> entered = outside(window, stable_);
  for (const CellBox& b : entered) {
    if (!b.empty()) see_all(map, local(b), true);
  }
  const LocalSlots slots(map);
  geometry_rows(map, slots);
  // A score changes with its own cell's geometry, known-ness and certainty
  // (marked above) and with the edge distance, which changes only within
  // the search radius of a cell that became or stopped being an edge: one
  // whose step crossed max_step_m, or one that left (a cell outside the
  // window stands in as its nearest window cell, which is no farther from
  // any window cell). A cell that became known since it entered gets its
  // first.
  grow(flips_, edge_rows_, edge_widths_);
  search_or_raise();
  for (std::size_t x = 0; x < edge_rows_.size(); ++x) {
    Span& u = unseen_edge_rows_[x];
    if (u.lo > u.hi) continue;
    Span& e = edge_rows_[x];
    e.lo = std::min(e.lo, u.lo);
    e.hi = std::max(e.hi, u.hi);
    u = Span{n_, -1};
  }
  edge_rows(map, false);
  raise_edges();
  score_rows(map);
  pending_.clear();
  window_ = stable_ = window;
}

void FootholdLayers::compute(ElevationMap& map) {
  set_slots(map);
  see_all(map, {0, n_ - 1, 0, n_ - 1}, false);
  std::fill(geometry_mark_.begin(), geometry_mark_.end(), std::uint8_t{1});
  std::fill(geometry_rows_.begin(), geometry_rows_.end(), Span{0, n_ - 1});
  std::fill(flips_.begin(), flips_.end(), Span{n_, -1});
  const LocalSlots slots(map);
  geometry_rows(map, slots);
  raised_.clear();  // every distance is searched for
  std::fill(edge_rows_.begin(), edge_rows_.end(), Span{0, n_ - 1});
  edge_rows(map, true);
  std::fill(score_mark_.begin(), score_mark_.end(), std::uint8_t{1});
  std::fill(score_rows_.begin(), score_rows_.end(), Span{0, n_ - 1});
  score_rows(map);
}

// Redoes the marked cells' geometry (clearing the marks and the rows'
// hulls); marks the score of a cell whose geometry changed and notes the
// cells whose step crossed max_step_m.
void FootholdLayers::geometry_rows(ElevationMap& map, const LocalSlots& slots) {
  std::size_t cells = 0;
  float* slope = map.data(slope_);
  float* roughness = map.data(roughness_);
  float* step = map.data(step_);
  const auto max_step = static_cast<float>(options_.max_step_m);
  const int f = static_cast<int>(foot_cells_);
  const bool fast = footprint_.size() <= kKept;
  raised_.clear();
  for (int i = 0; i < n_; ++i) {
    Span& s = geometry_rows_[static_cast<std::size_t>(i)];
    if (s.lo > s.hi) continue;
    Span& flip = flips_[static_cast<std::size_t>(i)];
    std::uint8_t* mark = geometry_mark_.data() + static_cast<std::size_t>(i) * static_cast<std::size_t>(n_);
    const bool inner_row = fast && i >= f && i < n_ - f;
    const std::size_t row = row_slot_[static_cast<std::size_t>(i)];
    for (int j = s.lo; j <= s.hi; ++j) {
      if (!mark[j]) continue;
      mark[j] = 0;
      ++cells;
      const std::size_t t = row + col_slot_[static_cast<std::size_t>(j)];
      const float old_slope = slope[t], old_roughness = roughness[t], old_step = step[t];
      if (inner_row && j >= f && j < n_ - f) {
        geometry_inside(map, i, j);
      } else {
        geometry_of(map, slots, {slots.corner.x + i, slots.corner.y + j});
      }
      if (!same_bits(old_slope, slope[t]) || !same_bits(old_roughness, roughness[t]) || !same_bits(old_step, step[t])) {
        mark_score(i, j);
      }
      const bool edge = step[t] > max_step;
      if (edge && !(old_step > max_step)) {
        raised_.push_back(static_cast<std::int32_t>(i * n_ + j));
      } else if (!edge && old_step > max_step) {
        flip.lo = std::min(flip.lo, j);
        flip.hi = std::max(flip.hi, j);
      }
    }
    s = Span{n_, -1};
  }
  last_geometry_cells_ = cells;
}

// geometry_of() for a cell whose whole footprint lies in the window: no
// bounds checks, slots from the per-row and per-column tables, known-ness
// and elevation from what this refresh saw (the map's, see_changes()).
// The same operations in the same order: the same bits.
void FootholdLayers::geometry_inside(ElevationMap& map, int i, int j) const {
  const float* seen = seen_elevation_.data();
  const std::size_t* rows = row_slot_.data() + i;
  const std::size_t* cols = col_slot_.data() + j;
  const std::size_t s = rows[0] + cols[0];
  float* slope = map.data(slope_);
  float* roughness = map.data(roughness_);
  float* step = map.data(step_);
  slope[s] = roughness[s] = step[s] = kNaN;
  if (std::isnan(seen[s])) return;
  const double z0 = seen[s];
  double b0 = 0.0, b1 = 0.0, b2 = 0.0;
  double lo = 0.0, hi = 0.0;
  std::size_t count = 0;
  std::array<double, kKept> kept_z;
  std::array<std::uint8_t, kKept> kept_k;
  const std::size_t m = footprint_.size();
  for (std::size_t k = 0; k < m; ++k) {
    const CellIndex& o = footprint_[k];
    const float e = seen[rows[o.x] + cols[o.y]];
    if (std::isnan(e)) continue;
    const double z = e - z0;
    b0 += z;
    b1 += foot_x_m_[k] * z;
    b2 += foot_y_m_[k] * z;
    lo = std::min(lo, z);
    hi = std::max(hi, z);
    kept_z[count] = z;
    kept_k[count] = static_cast<std::uint8_t>(k);
    ++count;
  }
  if (count < min_known_) return;
  step[s] = static_cast<float>(hi - lo);
  const Eigen::Matrix3d* inverse = &full_inverse_;
  Eigen::Matrix3d partial;
  if (count != m) {
    double sx = 0.0, sy = 0.0, sxx = 0.0, sxy = 0.0, syy = 0.0;
    for (std::size_t c = 0; c < count; ++c) {
      const double x = foot_x_m_[kept_k[c]], y = foot_y_m_[kept_k[c]];
      sx += x;
      sy += y;
      sxx += x * x;
      sxy += x * y;
      syy += y * y;
    }
    Eigen::Matrix3d a;
    a << static_cast<double>(count), sx, sy, sx, sxx, sxy, sy, sxy, syy;
    bool invertible = false;
    const double scale = cell_size_m_ * cell_size_m_;
    a.computeInverseWithCheck(partial, invertible, 1e-9 * scale * scale);
    if (!invertible) return;
    inverse = &partial;
  }
  const Eigen::Vector3d b(b0, b1, b2);
  const Eigen::Vector3d plane = *inverse * b;
  double residual2 = 0.0;
  for (std::size_t c = 0; c < count; ++c) {
    const std::size_t k = kept_k[c];
    // (plane * offset in cells) * cell size, as geometry_of(): the same bits.
    const double fit = plane[0] + plane[1] * foot_dx_[k] * cell_size_m_ + plane[2] * foot_dy_[k] * cell_size_m_;
    const double r = kept_z[c] - fit;
    residual2 += r * r;
  }
  slope[s] = static_cast<float>(std::atan(std::hypot(plane[1], plane[2])) * 180.0 / std::numbers::pi);
  roughness[s] = static_cast<float>(std::sqrt(residual2 / static_cast<double>(count)));
}

void FootholdLayers::geometry_of(ElevationMap& map, const LocalSlots& slots, CellIndex cell) const {
  const float* elevation = map.elevation_data();
  const std::uint8_t* state = map.state_data();
  const std::size_t s = slots.of(cell);
  float* slope = map.data(slope_);
  float* roughness = map.data(roughness_);
  float* step = map.data(step_);
  slope[s] = roughness[s] = step[s] = kNaN;
  if (!known(elevation, state, s)) return;
  // Elevations relative to the centre cell's keep the sums small, so the
  // residuals (millimetres) survive next to heights of metres.
  const double z0 = elevation[s];
  double sx = 0.0, sy = 0.0, sxx = 0.0, sxy = 0.0, syy = 0.0;
  Eigen::Vector3d b = Eigen::Vector3d::Zero();
  double lo = 0.0, hi = 0.0;
  std::size_t count = 0;
  // The known cells' relative elevations and offsets, kept for the
  // residuals so that the second pass does not look them up again (the
  // same values in the same order: the same bits).
  std::array<std::array<double, 3>, kKept> kept;
  const bool keep = footprint_.size() <= kKept;
  for (const CellIndex& o : footprint_) {
    const CellIndex q{cell.x + o.x, cell.y + o.y};
    if (!slots.inside(q)) continue;
    const std::size_t t = slots.of(q);
    if (!known(elevation, state, t)) continue;
    const double z = elevation[t] - z0;
    if (keep) kept[count] = {z, static_cast<double>(o.x), static_cast<double>(o.y)};
    const double x = static_cast<double>(o.x) * cell_size_m_, y = static_cast<double>(o.y) * cell_size_m_;
    sx += x;
    sy += y;
    sxx += x * x;
    sxy += x * y;
    syy += y * y;
    b += Eigen::Vector3d(z, x * z, y * z);
    lo = std::min(lo, z);
    hi = std::max(hi, z);
    ++count;
  }
  if (count < min_known_) return;
  step[s] = static_cast<float>(hi - lo);
  // A whole footprint (the common case) has the normal matrix inverted
  // once, when the layers were attached; only a partial one needs its own.
  Eigen::Matrix3d inverse = full_inverse_;
  if (count != footprint_.size()) {
    Eigen::Matrix3d a;
    a << static_cast<double>(count), sx, sy, sx, sxx, sxy, sy, sxy, syy;
    bool invertible = false;
    // Cell spacing squared sets the scale of the determinant: collinear
    // cells give one that vanishes relative to it.
    const double scale = cell_size_m_ * cell_size_m_;
    a.computeInverseWithCheck(inverse, invertible, 1e-9 * scale * scale);
    if (!invertible) return;
  }
  const Eigen::Vector3d plane = inverse * b;
  double residual2 = 0.0;
  if (keep) {
    for (std::size_t k = 0; k < count; ++k) {
      const double fit = plane[0] + plane[1] * kept[k][1] * cell_size_m_ + plane[2] * kept[k][2] * cell_size_m_;
      const double r = kept[k][0] - fit;
      residual2 += r * r;
    }
  }
  for (const CellIndex& o : keep ? std::span<const CellIndex>() : std::span<const CellIndex>(footprint_)) {
    const CellIndex q{cell.x + o.x, cell.y + o.y};
    if (!slots.inside(q)) continue;
    const std::size_t t = slots.of(q);
    if (!known(elevation, state, t)) continue;
    const double fit = plane[0] + plane[1] * static_cast<double>(o.x) * cell_size_m_ +
                       plane[2] * static_cast<double>(o.y) * cell_size_m_;
    const double r = (elevation[t] - z0) - fit;
    residual2 += r * r;
  }
  slope[s] = static_cast<float>(std::atan(std::hypot(plane[1], plane[2])) * 180.0 / std::numbers::pi);
  roughness[s] = static_cast<float>(std::sqrt(residual2 / static_cast<double>(count)));
}

// The edge distance of the cells in edge_rows_, stored in seen_edge2_;
// marks the score of a cell whose distance changed (all: every cell's).
void FootholdLayers::edge_rows(ElevationMap& map, bool all) {
  const float* step = map.data(step_);
  const int r = static_cast<int>(edge_cells_), none = r + 1;
  const std::int32_t none2 = r * r + 1;
  // Far beyond any r * r + r * r, and no overflow when dx * dx is added.
  constexpr std::int32_t kFar = 1 << 29;
  const auto max_step = static_cast<float>(options_.max_step_m);
  const auto n = static_cast<std::size_t>(n_);
  std::size_t cells = 0;
  // The along-row distances a row must supply: its columns wherever a row
  // within r of it has cells to redo.
  std::fill(distance_rows_.begin(), distance_rows_.end(), Span{n_, -1});
  for (int x = 0; x < n_; ++x) {
    const Span e = edge_rows_[static_cast<std::size_t>(x)];
    if (e.lo > e.hi) continue;
    for (int k = std::max(0, x - r); k <= std::min(n_ - 1, x + r); ++k) {
      Span& d = distance_rows_[static_cast<std::size_t>(k)];
      d.lo = std::min(d.lo, e.lo);
      d.hi = std::max(d.hi, e.hi);
    }
  }
  // Per row: the squared distance along the row to the nearest edge within
  // r (kFar beyond), two sweeps over the needed columns and r either side.
  for (int x = 0; x < n_; ++x) {
    const Span need = distance_rows_[static_cast<std::size_t>(x)];
    if (need.lo > need.hi) continue;
    std::int32_t* out = distance2_.data() + static_cast<std::size_t>(x) * n;
    const int lo = std::max(need.lo - r, 0), hi = std::min(need.hi + r, n_ - 1);
    const float* row = step + row_slot_[static_cast<std::size_t>(x)];
    const std::size_t* cols = col_slot_.data();
    int last = std::numeric_limits<int>::min() / 2;
    for (int y = lo; y <= hi; ++y) {
      if (row[cols[y]] > max_step) last = y;
      out[y] = std::min(none, y - last);
    }
    int next = std::numeric_limits<int>::max() / 2;
    for (int y = hi; y >= lo; --y) {
      if (row[cols[y]] > max_step) next = y;
      const int d = std::min(out[y], std::min(none, next - y));
      out[y] = d <= r ? d * d : kFar;
    }
  }
  for (int x = 0; x < n_; ++x) {
    const Span e = edge_rows_[static_cast<std::size_t>(x)];
    if (e.lo > e.hi) continue;
    // min over the rows within r of dx^2 + (along-row distance)^2: exact
    // within the search disc (the nearest edge in Euclidean distance is the
    // nearest along its own row). Contiguous, so it vectorises.
    cells += static_cast<std::size_t>(e.hi - e.lo + 1);
    std::int32_t* best = best2_.data();
    std::fill(best + e.lo, best + e.hi + 1, kFar);
    for (int k = std::max(0, x - r); k <= std::min(n_ - 1, x + r); ++k) {
      const std::int32_t dx2 = (k - x) * (k - x);
      const std::int32_t* row = distance2_.data() + static_cast<std::size_t>(k) * n;
      for (int y = e.lo; y <= e.hi; ++y) best[y] = std::min(best[y], dx2 + row[y]);
    }
    const std::size_t row = row_slot_[static_cast<std::size_t>(x)];
    for (int y = e.lo; y <= e.hi; ++y) {
      const std::int32_t b = std::min(best[y], none2);
      std::int32_t& seen = seen_edge2_[row + col_slot_[static_cast<std::size_t>(y)]];
      if (b != seen || all) {
        seen = b;
        mark_score(x, y);
      }
    }
  }
  last_edge_cells_ = cells;
}

// Cells that became edges are cheap one by one (raise_edges(), a pass over
// the search disc each), but a cluster of them costs less searched for as
// one region. Whichever costs less by the rough counts below (about ten
// instructions a disc cell raised, a hundred and fifty a cell searched;
// callgrind, the benchmark's walks) is taken: the values are the same.
void FootholdLayers::search_or_raise() {
  if (raised_.empty()) return;
  const auto area = [](const std::vector<Span>& rows) {
    std::size_t cells = 0;
    for (const Span& r : rows) cells += r.lo <= r.hi ? static_cast<std::size_t>(r.hi - r.lo + 1) : 0;
    return cells;
  };
  merged_ = flips_;
  for (const std::int32_t cell : raised_) {
    Span& m = merged_[static_cast<std::size_t>(cell / n_)];
    m.lo = std::min(m.lo, cell % n_);
    m.hi = std::max(m.hi, cell % n_);
  }
  grow(merged_, merged_rows_, edge_widths_);
  const std::size_t extra = area(merged_rows_) - area(edge_rows_);
  if (extra * 15 < raised_.size() * edge_disc_cells_) {
    edge_rows_.swap(merged_rows_);
    raised_.clear();
  }
}

// A cell that became an edge can only shorten the edge distances within
// the search radius: each becomes the smaller of what it was and the
// distance to the new edge, which is what the search would find (the
// edges that went are searched for in edge_rows(), before). A cell not
// yet known (kEdgeUnknown) is searched for when it is.
void FootholdLayers::raise_edges() {
  const int r = static_cast<int>(edge_cells_);
  for (const std::int32_t cell : raised_) {
    const int ei = cell / n_, ej = cell % n_;
    for (int dx = std::max(-r, -ei); dx <= std::min(r, n_ - 1 - ei); ++dx) {
      const int w = edge_widths_[static_cast<std::size_t>(dx + r)];
      const std::size_t row = row_slot_[static_cast<std::size_t>(ei + dx)];
      for (int dy = std::max(-w, -ej); dy <= std::min(w, n_ - 1 - ej); ++dy) {
        const std::int32_t d2 = dx * dx + dy * dy;
        std::int32_t& seen = seen_edge2_[row + col_slot_[static_cast<std::size_t>(ej + dy)]];
        if (d2 < seen) {
          seen = d2;
          mark_score(ei + dx, ej + dy);
        }
      }
    }
  }
  raised_.clear();
}

// Edge distance and score of the marked cells (clearing the marks and the
// rows' hulls).
void FootholdLayers::score_rows(ElevationMap& map) {
  const float* certainty = map.certainty_data();
  const float* step = map.data(step_);
  const float* slope = map.data(slope_);
  const float* roughness = map.data(roughness_);
  float* edge_distance = map.data(edge_distance_);
  float* score = map.data(score_);
  const std::int64_t none2 = edge_cells_ * edge_cells_ + 1;
  std::size_t cells = 0;
  for (int x = 0; x < n_; ++x) {
    Span& e = score_rows_[static_cast<std::size_t>(x)];
    if (e.lo > e.hi) continue;
    std::uint8_t* mark = score_mark_.data() + static_cast<std::size_t>(x) * static_cast<std::size_t>(n_);
    const std::size_t row = row_slot_[static_cast<std::size_t>(x)];
    for (int y = e.lo; y <= e.hi; ++y) {
      if (!mark[y]) continue;
      mark[y] = 0;
      ++cells;
      const std::size_t s = row + col_slot_[static_cast<std::size_t>(y)];
      if (std::isnan(seen_elevation_[s])) {
        edge_distance[s] = score[s] = kNaN;
        continue;
      }
      const std::int64_t b = seen_edge2_[s];
      const bool tabled = b < static_cast<std::int64_t>(edge_distance_of_.size());
      const double distance_m = tabled ? edge_distance_of_[static_cast<std::size_t>(b)] : edge_distance_m_of(b, none2);
      edge_distance[s] = static_cast<float>(distance_m);
      if (std::isnan(slope[s]) || std::isnan(step[s]) || std::isnan(roughness[s])) {
        score[s] = kNaN;
        continue;
      }
      const double edge_factor =
          tabled ? edge_factor_of_[static_cast<std::size_t>(b)] : edge_factor_of_distance(distance_m);
      score[s] = static_cast<float>(ramp_down(slope[s], options_.max_slope_deg) * ramp_down(step[s], options_.max_step_m) *
                                    ramp_down(roughness[s], options_.max_roughness_m) * edge_factor *
                                    certainty_factor(certainty[s]));
    }
    e = Span{n_, -1};
  }
  last_score_cells_ = cells;
}

}  // namespace stridemap
