#include "stridemap/live/map_window.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "stridemap/core/error.hpp"
#include "stridemap/pipeline/mapping_pipeline.hpp"

namespace stridemap {
namespace {

// The mapper ignores points this far out (TerrainMapper::apply); a centre
// beyond it could never hold a measurement.
constexpr double kMaxCentre_m = 1.0e6;

std::string metres(double value) {
  char text[48];
  std::snprintf(text, sizeof text, "%.2f", value);
  return text;
}

double coordinate(const std::string& part, const std::string& text, const std::string& option) {
  char* end = nullptr;
  const double value = std::strtod(part.c_str(), &end);
  if (part.empty() || *end != '\0' || !std::isfinite(value)) {
    throw InputError(option + ": '" + text +
                     "' is neither fit nor a centre X,Y in metres (e.g. --window 1.5,-0.2 or --window fit)");
  }
  if (std::abs(value) > kMaxCentre_m) {
    throw InputError(option + ": '" + text + "': the centre must lie within 1000 km of the map origin");
  }
  return value;
}

}  // namespace

WindowChoice parse_window_choice(const std::string& text, const std::string& option) {
  WindowChoice choice;
  if (text.empty()) return choice;
  if (text == "fit") {
    choice.mode = WindowChoice::Mode::fit;
    return choice;
  }
  const std::size_t comma = text.find(',');
  if (comma == std::string::npos || text.find(',', comma + 1) != std::string::npos) {
    coordinate("", text, option);  // throws the message that says what is expected
  }
  choice.mode = WindowChoice::Mode::center;
  choice.center_m = {coordinate(text.substr(0, comma), text, option), coordinate(text.substr(comma + 1), text, option)};
  return choice;
}

void FootprintExtent::add(double x_m, double y_m) {
  min_m = min_m.cwiseMin(Eigen::Vector2d(x_m, y_m));
  max_m = max_m.cwiseMax(Eigen::Vector2d(x_m, y_m));
}

WindowPlacement window_centred_at(const GridOptions& grid, const Eigen::Vector2d& center_m) {
  validate_grid_options(grid);
  const int n = grid.cells_per_side;
  // The arithmetic of ElevationMap::cell_of / move_to.
  const auto cx = static_cast<std::int64_t>(std::floor(center_m.x() / grid.cell_size_m));
  const auto cy = static_cast<std::int64_t>(std::floor(center_m.y() / grid.cell_size_m));
  return {n, {cx - n / 2, cy - n / 2}};
}

WindowPlacement window_fitting(const GridOptions& grid, const FootprintExtent& extent) {
  validate_grid_options(grid);
  if (extent.empty()) {
    throw InputError("--window fit: no scan of the run could be placed (none got a pose), so there is nothing to fit");
  }
  const double c = grid.cell_size_m;
  // In double until the counts are known to fit: a stray far point must
  // give the message below, not an overflow.
  const double lo_x = std::floor(extent.min_m.x() / c), hi_x = std::floor(extent.max_m.x() / c);
  const double lo_y = std::floor(extent.min_m.y() / c), hi_y = std::floor(extent.max_m.y() / c);
  const double nx = hi_x - lo_x + 1.0, ny = hi_y - lo_y + 1.0;
  const double needed = std::max(nx, ny);
  if (!(needed <= kMaxGridCellsPerSide)) {
    throw GridSizeError(
        "--window fit: the run's points span " + metres(extent.max_m.x() - extent.min_m.x()) + " x " +
        metres(extent.max_m.y() - extent.min_m.y()) + " m (x " + metres(extent.min_m.x()) + ".." +
        metres(extent.max_m.x()) + ", y " + metres(extent.min_m.y()) + ".." + metres(extent.max_m.y()) +
        " m); with " + metres(c * 1000.0) + " mm cells that needs " + std::to_string(static_cast<long long>(needed)) +
        " cells a side (" + byte_size_text(needed * needed * static_cast<double>(kGridBytesPerCell)) +
        "), beyond the limit of " + std::to_string(kMaxGridCellsPerSide) +
        "; give larger cells (map.cell_size_m in --config) or place the window with --window X,Y");
  }
  const int n = std::max(grid.cells_per_side, static_cast<int>(needed));
  // The extent in the middle: the margin split evenly, the odd cell above.
  const auto corner = [n](double lo, double count) {
    return static_cast<std::int64_t>(lo) - (n - static_cast<std::int64_t>(count)) / 2;
  };
  return {n, {corner(lo_x, nx), corner(lo_y, ny)}};
}

// ---------------------------------------------------------------- the pass

struct FootprintPass::State final : PipelineObserver {
  explicit State(const PipelineOptions& options) : pipeline(options) {
    pipeline.integrator().set_collect_points(true);
    pipeline.integrator().add_observer(*this);
  }
  void on_scan(const ScanReport& report) override {
    if (report.stats.pose_rejected || report.stats.time_rejected) return;  // the mapper used nothing of it
    extent.add(report.payload.pose.x_m, report.payload.pose.y_m);
    ++extent.poses;
    for (const IntegratedPoint& p : pipeline.integrator().last_points()) {
      extent.add(p.map_m.x(), p.map_m.y());
      ++extent.points;
    }
  }

  MappingPipeline pipeline;
  FootprintExtent extent;
};

namespace {
PipelineOptions pass_options(const ScanMapperOptions& options, const UrgParameters& sensor) {
  PipelineOptions p = ScanMapper::pipeline_options(options, sensor);
  // The points are read off before the map; a one-cell map keeps the pass
  // from holding a second full-size grid.
  p.mapper.grid.cells_per_side = 1;
  p.mapper.grid.extra_layers.clear();
  p.height_fusion.enabled = false;  // no layers to fuse into
  return p;
}
}  // namespace

FootprintPass::FootprintPass(const ScanMapperOptions& options, const UrgParameters& sensor)
    : state_(std::make_unique<State>(pass_options(options, sensor))) {}

FootprintPass::~FootprintPass() = default;

void FootprintPass::add(const UrgRawScan& raw, PoseTrack& poses) {
  state_->pipeline.queue(raw);
  state_->pipeline.process(poses, true);
}

const FootprintExtent& FootprintPass::finish() {
  state_->pipeline.finish();
  return state_->extent;
}

std::size_t FootprintPass::scans_placed() const { return state_->pipeline.stats().integrated; }

}  // namespace stridemap
