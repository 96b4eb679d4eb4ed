#include "stridemap/core/foothold.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
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
  ring_rows_.assign(static_cast<std::size_t>(2 * edge_cells_ + 1), nullptr);
  row_distance_.assign(static_cast<std::size_t>(2 * edge_cells_ + 1) * static_cast<std::size_t>(n_), 0);
}

void FootholdLayers::recompute_all(ElevationMap& map) {
  const CellBox all = CellBox::window_of(map);
  last_geometry_cells_ = 0;
  geometry_in(map, all);
  edges_and_score_in(map, all);
  corner_ = map.min_cell();
  has_corner_ = true;
}

void FootholdLayers::update(ElevationMap& map, const CellBox& changed) {
  // The cells that left with a move of the window were neighbours of cells
  // that stayed: those lose them, as if the cells had become unknown.
  std::array<CellBox, 3> sources{changed, {}, {}};
  const CellIndex now = map.min_cell();
  if (has_corner_ && !(now == corner_)) {
    const std::int64_t n = n_;
    const CellBox before{corner_, {corner_.x + n - 1, corner_.y + n - 1}};
    if (now.x > corner_.x) sources[1] = {before.min, {std::min(before.max.x, now.x - 1), before.max.y}};
    if (now.x < corner_.x) sources[1] = {{std::max(before.min.x, now.x + n), before.min.y}, before.max};
    if (now.y > corner_.y) sources[2] = {before.min, {before.max.x, std::min(before.max.y, now.y - 1)}};
    if (now.y < corner_.y) sources[2] = {{before.min.x, std::max(before.min.y, now.y + n)}, before.max};
  }
  corner_ = now;
  has_corner_ = true;
  last_geometry_cells_ = 0;
  for (const CellBox& b : sources) geometry_in(map, b.grown(foot_cells_).clipped_to(map));
  for (const CellBox& b : sources) edges_and_score_in(map, b.grown(foot_cells_ + edge_cells_).clipped_to(map));
}

void FootholdLayers::geometry_in(ElevationMap& map, const CellBox& box) {
  if (box.empty()) return;
  const LocalSlots slots(map);
  for (std::int64_t x = box.min.x; x <= box.max.x; ++x) {
    for (std::int64_t y = box.min.y; y <= box.max.y; ++y) geometry_of(map, slots, {x, y});
  }
  last_geometry_cells_ += static_cast<std::size_t>((box.max.x - box.min.x + 1) * (box.max.y - box.min.y + 1));
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
  for (const CellIndex& o : footprint_) {
    const CellIndex q{cell.x + o.x, cell.y + o.y};
    if (!slots.inside(q)) continue;
    const std::size_t t = slots.of(q);
    if (!known(elevation, state, t)) continue;
    const double z = elevation[t] - z0;
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
  for (const CellIndex& o : footprint_) {
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

void FootholdLayers::edges_and_score_in(ElevationMap& map, const CellBox& box) {
  if (box.empty()) return;
  const LocalSlots slots(map);
  const float* elevation = map.elevation_data();
  const std::uint8_t* state = map.state_data();
  const float* certainty = map.certainty_data();
  const float* step = map.data(step_);
  const float* slope = map.data(slope_);
  const float* roughness = map.data(roughness_);
  float* edge_distance = map.data(edge_distance_);
  float* score = map.data(score_);
  const std::int64_t r = edge_cells_, none = r + 1, ring = 2 * r + 1;
  const std::int64_t width = box.max.y - box.min.y + 1;
  const auto max_step = static_cast<float>(options_.max_step_m);
  const CellBox window = CellBox::window_of(map);
  // Per row of the search band: the distance in cells along the row to the
  // nearest edge within r (none beyond), for the box's columns. Rows are
  // kept in a ring of 2r + 1, so each is computed once.
  const auto fill_row = [&](std::int64_t x) {
    int* out = row_distance_.data() + ((x - box.min.x + r) % ring) * n_;
    std::fill(out, out + width, static_cast<int>(none));
    if (x < window.min.x || x > window.max.x) return;
    const std::int64_t lo = std::max(box.min.y - r, window.min.y), hi = std::min(box.max.y + r, window.max.y);
    std::int64_t last = std::numeric_limits<std::int64_t>::min() / 2;
    for (std::int64_t y = lo; y <= hi; ++y) {
      if (step[slots.of({x, y})] > max_step) last = y;
      if (y >= box.min.y && y <= box.max.y) out[y - box.min.y] = static_cast<int>(std::min(none, y - last));
    }
    std::int64_t next = std::numeric_limits<std::int64_t>::max() / 2;
    for (std::int64_t y = hi; y >= lo; --y) {
      if (step[slots.of({x, y})] > max_step) next = y;
      if (y >= box.min.y && y <= box.max.y) {
        int& d = out[y - box.min.y];
        d = static_cast<int>(std::min<std::int64_t>(d, std::min(none, next - y)));
      }
    }
  };
  for (std::int64_t x = box.min.x - r; x < box.min.x + r; ++x) fill_row(x);
  const double cap_m = options_.edge_search_radius_m;
  for (std::int64_t x = box.min.x; x <= box.max.x; ++x) {
    fill_row(x + r);
    // The rows x - r .. x + r of the ring, in order: no modulo per cell.
    for (std::int64_t k = 0; k < ring; ++k) ring_rows_[static_cast<std::size_t>(k)] = row_distance_.data() + ((x + k - box.min.x) % ring) * n_;
    for (std::int64_t y = box.min.y; y <= box.max.y; ++y) {
      const std::size_t s = slots.of({x, y});
      if (!known(elevation, state, s)) {
        edge_distance[s] = score[s] = kNaN;
        continue;
      }
      std::int64_t best = std::numeric_limits<std::int64_t>::max();
      const std::int64_t column = y - box.min.y;
      for (std::int64_t k = 0; k < ring; ++k) {
        const std::int64_t d = ring_rows_[static_cast<std::size_t>(k)][column], dx = k - r;
        if (d <= r) best = std::min(best, dx * dx + d * d);
      }
      const double distance_m =
          best <= r * r ? std::sqrt(static_cast<double>(best)) * cell_size_m_ : cap_m;
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
}

}  // namespace stridemap
