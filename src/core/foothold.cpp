#include "stridemap/core/foothold.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <span>
#include <string>

#include <Eigen/Dense>

#include "stridemap/core/error.hpp"

namespace stridemap {
namespace {

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
      if (static_cast<double>(dx * dx + dy * dy) <= foot_cells * foot_cells) footprint_.push_back({dx, dy});
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
  const auto n = static_cast<std::size_t>(n_);
  pending_.resize(n_);
  seeds_.assign(n + 2 * static_cast<std::size_t>(foot_cells_), Span{1, 0});
  geometry_rows_.assign(n, Span{1, 0});
  score_rows_.assign(n, Span{1, 0});
  distance_rows_.assign(n, Span{1, 0});
  flips_.assign(n, Span{1, 0});
  distance2_.assign(n * n, 0);
  best2_.assign(n, 0);
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
  std::fill(geometry_rows_.begin(), geometry_rows_.end(), Span{0, n_ - 1});
  std::fill(score_rows_.begin(), score_rows_.end(), Span{0, n_ - 1});
  compute(map);
  pending_.clear();
  window_ = stable_ = CellBox::window_of(map);
  computed_ = true;
}

void FootholdLayers::seed_box(const CellBox& box, CellIndex corner) {
  // Local rows -f .. n - 1 + f, columns clipped the same: a change farther
  // out reaches no cell of the window.
  const std::int64_t f = foot_cells_, n = n_;
  const std::int64_t x0 = std::max(box.min.x - corner.x, -f), x1 = std::min(box.max.x - corner.x, n - 1 + f);
  const std::int64_t y0 = std::max(box.min.y - corner.y, -f), y1 = std::min(box.max.y - corner.y, n - 1 + f);
  if (y0 > y1) return;
  for (std::int64_t x = x0; x <= x1; ++x) {
    Span& s = seeds_[static_cast<std::size_t>(x + f)];
    s.lo = std::min(s.lo, static_cast<int>(y0));
    s.hi = std::max(s.hi, static_cast<int>(y1));
  }
}

// to[x] covers from[x + dx] widened by widths[dx + r] for |dx| <= r (the
// rows' hulls: a bound of the disc around every cell of `from`), for the
// window's rows. from[i] is row i - from_offset.
void FootholdLayers::grow(const std::vector<Span>& from, int from_offset, std::vector<Span>& to,
                          const std::vector<int>& widths) {
  const int r = static_cast<int>(widths.size() / 2);
  std::fill(to.begin(), to.end(), Span{n_, -1});
  for (int i = 0; i < static_cast<int>(from.size()); ++i) {
    const Span s = from[static_cast<std::size_t>(i)];
    if (s.lo > s.hi) continue;
    const int x = i - from_offset;
    for (int dx = std::max(-r, -x); dx <= r && x + dx < n_; ++dx) {
      const int w = widths[static_cast<std::size_t>(dx + r)];
      if (w < 0) continue;
      Span& t = to[static_cast<std::size_t>(x + dx)];
      t.lo = std::min(t.lo, std::max(s.lo - w, 0));
      t.hi = std::max(t.hi, std::min(s.hi + w, n_ - 1));
    }
  }
}

void FootholdLayers::refresh(ElevationMap& map) {
  if (!computed_) {
    recompute_all(map);
    return;
  }
  const CellBox window = CellBox::window_of(map);
  stable_ = stable_.intersected(window);
  last_geometry_cells_ = last_score_cells_ = 0;
  if (pending_.empty() && stable_ == window_ && window_ == window) return;
  if (stable_.empty()) {  // the window jumped by a whole window or more
    recompute_all(map);
    return;
  }
  const CellIndex corner = window.min;
  std::fill(seeds_.begin(), seeds_.end(), Span{std::numeric_limits<int>::max(), std::numeric_limits<int>::min()});
  // Changed cells still in the window. One that left since is among the
  // cells that left, below; one that came and went never was a neighbour.
  if (!pending_.empty()) {
    const CellBox rows = pending_.bounds().intersected(window);
    std::int64_t lo = 0, hi = 0;
    for (std::int64_t x = rows.min.x; !rows.empty() && x <= rows.max.x; ++x) {
      if (pending_.span(x, lo, hi)) seed_box({{x, lo}, {x, hi}}, corner);
    }
  }
  // Cells of the last refresh's window outside every window since: they
  // left (and may have come back reset), so their neighbours lost them.
  // Cells that entered were unknown before and after: no change.
  std::array<CellBox, 4> left{};
  if (!(stable_ == window_)) {
    const CellBox& w = window_;
    const CellBox& s = stable_;
    if (w.min.x < s.min.x) left[0] = {w.min, {s.min.x - 1, w.max.y}};
    if (s.max.x < w.max.x) left[1] = {{s.max.x + 1, w.min.y}, w.max};
    if (w.min.y < s.min.y) left[2] = {{s.min.x, w.min.y}, {s.max.x, s.min.y - 1}};
    if (s.max.y < w.max.y) left[3] = {{s.min.x, s.max.y + 1}, {s.max.x, w.max.y}};
    for (const CellBox& b : left) {
      if (!b.empty()) seed_box(b, corner);
    }
  }
  grow(seeds_, static_cast<int>(foot_cells_), geometry_rows_, foot_widths_);
  const LocalSlots slots(map);
  geometry_rows(map, slots);
  // A score changes with its own cell's geometry and certainty (both
  // within the geometry rows) and with the edge distance, which changes
  // only within the search radius of a cell that became or stopped being
  // an edge: one whose step crossed max_step_m, or one that left (its
  // step layer may since have been reset, so no crossing shows). A cell
  // outside the window stands in as its nearest window cell, which is no
  // farther from any window cell.
  for (const CellBox& b : left) {
    if (b.empty()) continue;
    const auto clamp = [&](std::int64_t v) { return static_cast<int>(std::clamp<std::int64_t>(v, 0, n_ - 1)); };
    const int y0 = clamp(b.min.y - corner.y), y1 = clamp(b.max.y - corner.y);
    for (int x = clamp(b.min.x - corner.x); x <= clamp(b.max.x - corner.x); ++x) {
      Span& f = flips_[static_cast<std::size_t>(x)];
      f.lo = std::min(f.lo, y0);
      f.hi = std::max(f.hi, y1);
    }
  }
  grow(flips_, 0, score_rows_, edge_widths_);
  for (std::size_t i = 0; i < score_rows_.size(); ++i) {
    const Span g = geometry_rows_[i];
    if (g.lo > g.hi) continue;
    score_rows_[i].lo = std::min(score_rows_[i].lo, g.lo);
    score_rows_[i].hi = std::max(score_rows_[i].hi, g.hi);
  }
  edges_and_score_rows(map, slots);
  pending_.clear();
  window_ = stable_ = window;
}

void FootholdLayers::compute(ElevationMap& map) {
  const LocalSlots slots(map);
  geometry_rows(map, slots);
  edges_and_score_rows(map, slots);
}

void FootholdLayers::geometry_rows(ElevationMap& map, const LocalSlots& slots) {
  std::size_t cells = 0;
  const float* step = map.data(step_);
  const auto max_step = static_cast<float>(options_.max_step_m);
  for (int i = 0; i < n_; ++i) {
    const Span s = geometry_rows_[static_cast<std::size_t>(i)];
    Span& flip = flips_[static_cast<std::size_t>(i)];
    flip = Span{n_, -1};
    for (int j = s.lo; j <= s.hi; ++j) {
      const CellIndex c{slots.corner.x + i, slots.corner.y + j};
      const std::size_t t = slots.of(c);
      const bool was_edge = step[t] > max_step;
      geometry_of(map, slots, c);
      if ((step[t] > max_step) != was_edge) {
        flip.lo = std::min(flip.lo, j);
        flip.hi = std::max(flip.hi, j);
      }
    }
    if (s.lo <= s.hi) cells += static_cast<std::size_t>(s.hi - s.lo + 1);
  }
  last_geometry_cells_ = cells;
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
  constexpr std::size_t kKept = 64;
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

void FootholdLayers::edges_and_score_rows(ElevationMap& map, const LocalSlots& slots) {
  const float* elevation = map.elevation_data();
  const std::uint8_t* state = map.state_data();
  const float* certainty = map.certainty_data();
  const float* step = map.data(step_);
  const float* slope = map.data(slope_);
  const float* roughness = map.data(roughness_);
  float* edge_distance = map.data(edge_distance_);
  float* score = map.data(score_);
  const int r = static_cast<int>(edge_cells_), none = r + 1;
  // Far beyond any r * r + r * r, and no overflow when dx * dx is added.
  constexpr std::int32_t kFar = 1 << 29;
  const auto max_step = static_cast<float>(options_.max_step_m);
  const auto n = static_cast<std::size_t>(n_);
  // The along-row distances a row must supply: its columns wherever a row
  // within r of it has cells to redo.
  std::fill(distance_rows_.begin(), distance_rows_.end(), Span{n_, -1});
  for (int x = 0; x < n_; ++x) {
    const Span e = score_rows_[static_cast<std::size_t>(x)];
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
    const std::size_t row_slot = slots.of({slots.corner.x + x, slots.corner.y});
    const std::size_t row_start = row_slot - row_slot % n;
    const auto step_at = [&](int y) {
      std::size_t j = row_slot % n + static_cast<std::size_t>(y);
      if (j >= n) j -= n;
      return step[row_start + j];
    };
    int last = std::numeric_limits<int>::min() / 2;
    for (int y = lo; y <= hi; ++y) {
      if (step_at(y) > max_step) last = y;
      out[y] = std::min(none, y - last);
    }
    int next = std::numeric_limits<int>::max() / 2;
    for (int y = hi; y >= lo; --y) {
      if (step_at(y) > max_step) next = y;
      const int d = std::min(out[y], std::min(none, next - y));
      out[y] = d <= r ? d * d : kFar;
    }
  }
  const double cap_m = options_.edge_search_radius_m;
  std::size_t cells = 0;
  for (int x = 0; x < n_; ++x) {
    const Span e = score_rows_[static_cast<std::size_t>(x)];
    if (e.lo > e.hi) continue;
    cells += static_cast<std::size_t>(e.hi - e.lo + 1);
    // min over the rows within r of dx^2 + (along-row distance)^2: exact
    // within the search disc (the nearest edge in Euclidean distance is the
    // nearest along its own row). Contiguous, so it vectorises.
    std::int32_t* best = best2_.data();
    std::fill(best + e.lo, best + e.hi + 1, kFar);
    for (int k = std::max(0, x - r); k <= std::min(n_ - 1, x + r); ++k) {
      const std::int32_t dx2 = (k - x) * (k - x);
      const std::int32_t* row = distance2_.data() + static_cast<std::size_t>(k) * n;
      for (int y = e.lo; y <= e.hi; ++y) best[y] = std::min(best[y], dx2 + row[y]);
    }
    for (int y = e.lo; y <= e.hi; ++y) {
      const std::size_t s = slots.of({slots.corner.x + x, slots.corner.y + y});
      if (!known(elevation, state, s)) {
        edge_distance[s] = score[s] = kNaN;
        continue;
      }
      const std::int64_t b = best[y];
      const double distance_m =
          b <= static_cast<std::int64_t>(r) * r ? std::sqrt(static_cast<double>(b)) * cell_size_m_ : cap_m;
      edge_distance[s] = static_cast<float>(distance_m);
      if (std::isnan(slope[s]) || std::isnan(step[s]) || std::isnan(roughness[s])) {
        score[s] = kNaN;
        continue;
      }
      const double edge_factor =
          options_.edge_clearance_m > 0.0 ? std::min(1.0, distance_m / options_.edge_clearance_m) : 1.0;
      const double certainty_factor = std::clamp(static_cast<double>(certainty[s]) / options_.full_certainty, 0.0, 1.0);
      score[s] = static_cast<float>(ramp_down(slope[s], options_.max_slope_deg) * ramp_down(step[s], options_.max_step_m) *
                                    ramp_down(roughness[s], options_.max_roughness_m) * edge_factor * certainty_factor);
    }
  }
  last_score_cells_ = cells;
}

}  // namespace stridemap
