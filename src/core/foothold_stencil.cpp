#include "stridemap/core/foothold_stencil.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include <Eigen/Dense>

namespace stridemap {

FootholdStencil::FootholdStencil(double foot_radius_m, double edge_search_radius_m, double min_known_fraction,
                                 double cell_size_m_in, int cells_per_side)
    : cell_size_m(cell_size_m_in) {
  // A relative epsilon keeps a radius that is a whole number of cells from
  // losing its outermost ring to rounding (0.03 / 0.01 = 2.9999...).
  const double foot_radius_cells = foot_radius_m / cell_size_m * (1.0 + 1e-9);
  foot_cells = static_cast<std::int64_t>(std::floor(foot_radius_cells));
  edge_cells = static_cast<std::int64_t>(std::floor(edge_search_radius_m / cell_size_m * (1.0 + 1e-9)));
  edge_cells = std::min<std::int64_t>(edge_cells, cells_per_side);
  for (std::int64_t dx = -foot_cells; dx <= foot_cells; ++dx) {
    for (std::int64_t dy = -foot_cells; dy <= foot_cells; ++dy) {
      if (static_cast<double>(dx * dx + dy * dy) <= foot_radius_cells * foot_radius_cells) {
        footprint.push_back({dx, dy});
        foot_x_m.push_back(static_cast<double>(dx) * cell_size_m);
        foot_y_m.push_back(static_cast<double>(dy) * cell_size_m);
        foot_dx.push_back(static_cast<double>(dx));
        foot_dy.push_back(static_cast<double>(dy));
      }
    }
  }
  min_known = std::max<std::size_t>(
      3, static_cast<std::size_t>(std::ceil(min_known_fraction * static_cast<double>(footprint.size()))));
  min_known = std::min(min_known, std::max<std::size_t>(footprint.size(), 3));
  Eigen::Matrix3d full = Eigen::Matrix3d::Zero();
  for (const CellIndex& o : footprint) {
    const Eigen::Vector3d v(1.0, static_cast<double>(o.x) * cell_size_m, static_cast<double>(o.y) * cell_size_m);
    full.noalias() += v * v.transpose();
  }
  full_inverse = Eigen::Matrix3d::Zero();
  if (footprint.size() >= 3) full_inverse = full.inverse();
  // The same predicates as the footprint's and the edge search's.
  for (std::int64_t dx = -foot_cells; dx <= foot_cells; ++dx) {
    int w = 0;
    while (w + 1 <= foot_cells &&
           static_cast<double>(dx * dx + (w + 1) * (w + 1)) <= foot_radius_cells * foot_radius_cells) {
      ++w;
    }
    foot_widths.push_back(static_cast<double>(dx * dx) <= foot_radius_cells * foot_radius_cells ? w : -1);
  }
  for (std::int64_t dx = -edge_cells; dx <= edge_cells; ++dx) {
    int w = 0;
    while (w + 1 <= edge_cells && dx * dx + (w + 1) * (w + 1) <= edge_cells * edge_cells) ++w;
    edge_widths.push_back(w);
  }
  for (const int w : edge_widths) edge_disc_cells += static_cast<std::size_t>(2 * w + 1);
}

void grow_rows(const std::vector<RowSpan>& from, std::vector<RowSpan>& to, const std::vector<int>& widths) {
  const int n = static_cast<int>(from.size());
  const int r = static_cast<int>(widths.size() / 2);
  std::fill(to.begin(), to.end(), RowSpan{n, -1});
  for (int x = 0; x < n; ++x) {
    const RowSpan s = from[static_cast<std::size_t>(x)];
    if (s.lo > s.hi) continue;
    for (int dx = std::max(-r, -x); dx <= r && x + dx < n; ++dx) {
      const int w = widths[static_cast<std::size_t>(dx + r)];
      if (w < 0) continue;
      RowSpan& t = to[static_cast<std::size_t>(x + dx)];
      t.lo = std::min(t.lo, std::max(s.lo - w, 0));
      t.hi = std::max(t.hi, std::min(s.hi + w, n - 1));
    }
  }
}

PaddedElevations::PaddedElevations(int cells_per_side, std::int64_t foot_cells)
    : n(cells_per_side),
      margin(foot_cells),
      stride(cells_per_side + 2 * foot_cells + kFootholdLanes),
      values(static_cast<std::size_t>((cells_per_side + 2 * foot_cells) * stride),
             std::numeric_limits<float>::quiet_NaN()),
      needed(static_cast<std::size_t>(cells_per_side), RowSpan{cells_per_side, -1}) {}

void PaddedElevations::copy(const std::vector<RowSpan>& marked, const std::vector<float>& seen,
                            const std::vector<std::size_t>& row_slot, const std::vector<std::size_t>& col_slot) {
  const int f = static_cast<int>(margin);
  std::fill(needed.begin(), needed.end(), RowSpan{n, -1});
  for (int x = 0; x < n; ++x) {
    const RowSpan s = marked[static_cast<std::size_t>(x)];
    if (s.lo > s.hi) continue;
    for (int k = std::max(0, x - f); k <= std::min(n - 1, x + f); ++k) {
      RowSpan& r = needed[static_cast<std::size_t>(k)];
      r.lo = std::min(r.lo, std::max(0, s.lo - f));
      r.hi = std::max(r.hi, std::min(n - 1, s.hi + f));
    }
  }
  const auto cells = static_cast<std::size_t>(n);
  for (int x = 0; x < n; ++x) {
    const RowSpan r = needed[static_cast<std::size_t>(x)];
    float* to = values.data() + (x + margin) * stride + margin;
    const float* from = seen.data() + row_slot[static_cast<std::size_t>(x)];
    // Storage columns wrap round once: at most two runs.
    for (int y = r.lo; y <= r.hi;) {
      const std::size_t s = col_slot[static_cast<std::size_t>(y)];
      const int run = static_cast<int>(std::min<std::size_t>(static_cast<std::size_t>(r.hi - y + 1), cells - s));
      std::memcpy(to + y, from + s, static_cast<std::size_t>(run) * sizeof(float));
      y += run;
    }
  }
}

}  // namespace stridemap
