#pragma once
// Measures the boxes and cylinders of a scene from an elevation map, as the
// paper measures its boxes in Table 1: length (along the rail, X), width
// (across it, Y) and height above the ground around the object.
#include <array>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "stridemap/experiments/box_edges.hpp"
#include "stridemap/experiments/map_evaluation.hpp"
#include "stridemap/sim/scene.hpp"

namespace stridemap {

struct ObjectDimensions {
  double length_m = 0.0;
  double width_m = 0.0;
  double height_m = 0.0;
};

/// How a box's length and width are read from its region of cells.
enum class ExtentEstimate : std::uint8_t {
  /// Sub-cell: the four edges fitted to the positions of the readings that
  /// set the region's edge cells (experiments/box_edges.hpp, trimmed); the
  /// map must hold the top-point layers (core/top_point.hpp), else the
  /// second moments below are used.
  edges,
  /// From the second moment of the region's cell centres along each axis,
  /// L = sqrt(12 var + s^2) - s: every cell counts, so where an edge falls
  /// inside its cell moves the estimate by a fraction of a cell, not by one.
  moments,
  /// The spread of the rows holding at least half as many cells as the
  /// fullest (whole cells; a few stray cells along an edge do not count).
  trimmed,
  /// The spread of all the region's cell centres (whole cells).
  untrimmed,
};

/// A box's sides as the sensor met them: near faces the way it came from,
/// far the way it went, left and right of its travel.
enum class EdgeSide : std::uint8_t { near, far, left, right };
const char* to_string(EdgeSide side);

struct ObjectMeasurement {
  static constexpr double kUnmeasured = std::numeric_limits<double>::quiet_NaN();
  std::string name;
  std::string kind;  ///< "box" or "cylinder"
  ObjectDimensions truth;
  /// By ObjectMeasureOptions::extent (and height, the same in all three).
  ObjectDimensions measured;
  /// Whole cells: ExtentEstimate::trimmed and untrimmed.
  ObjectDimensions measured_trimmed;
  ObjectDimensions measured_untrimmed;
  /// Sub-cell edge fits, trimmed and with every reading (NaN extents when
  /// the map has no top-point layers or a side has too few readings).
  ObjectDimensions edges_trimmed;
  ObjectDimensions edges_untrimmed;
  /// The box's yaw as read from the map (the trimmed edge fit's, else the
  /// minimum-area rectangle of its cells; length along it) [rad].
  double measured_yaw_rad = 0.0;
  /// Boxes: each edge of the trimmed fit against the truth's, outwards
  /// positive [m], in the order of EdgeSide (named from
  /// ObjectMeasureOptions::travel_heading_rad); NaN without that fit.
  std::array<double, 4> edge_errors_m{kUnmeasured, kUnmeasured, kUnmeasured, kUnmeasured};
  /// The share of the object's top the ideal sensor saw on the run
  /// (experiments/top_visibility.hpp), in [0, 1]; NaN when not worked out.
  double seen_share = kUnmeasured;
  bool found = false;  ///< false when the map holds no cell above the half-height threshold
  std::size_t cells = 0;  ///< cells of the connected region taken as the object
};

struct ObjectMeasureOptions {
  /// The first guess of the local ground is the median of the known cells
  /// within this distance of the object's centre [m].
  double neighbourhood_m = 0.35;
  /// Width of the ring around the object's region whose median elevation
  /// is the local ground its height is measured from [m].
  double ground_ring_m = 0.05;
  /// A cell belongs to the object when it rises above the local ground by
  /// at least this fraction of the object's height in the map.
  double height_fraction = 0.5;
  /// The sub-cell edges are fitted to the border of the box's top: the
  /// region's cells at most this far below its median top [m] (and never
  /// below the region's threshold).
  double edge_band_m = 0.006;
  ExtentEstimate extent = ExtentEstimate::edges;
  /// The direction the sensor travelled (map frame) [rad]: it names the
  /// sides of ObjectMeasurement::edge_errors_m.
  double travel_heading_rad = 0.0;
  /// A point on the line the sensor travelled (map frame) [m]; NaN when
  /// unknown. Each object's edge fit gets it in its own frame
  /// (BoxEdgeOptions::view_path_point_m).
  Eigen::Vector2d travel_point_m = Eigen::Vector2d::Constant(std::numeric_limits<double>::quiet_NaN());
  /// The height of the scanner's origin in the map frame while it travelled
  /// [m]; NaN when unknown, and then the readings stay where they are. A
  /// cell keeps its highest reading (eq. (10)), one whose range came short,
  /// which lies up its beam, towards the sensor: at a side running along
  /// the track, inwards by its height over the top times the beam's
  /// across-track run over its drop. Known, the sides along the view take
  /// their readings moved back along that run to the top's level
  /// (fit_box_edges's `level_readings`). Along the track see
  /// sensor_pitch_rad.
  double sensor_height_m = std::numeric_limits<double>::quiet_NaN();
  /// The scan plane's pitch below the horizontal [rad], in (0, pi/2), for a
  /// planar scanner turned about its across-track axis only; NaN when
  /// unknown (or the scanner is rolled or yawed), and then the near and far
  /// sides keep their readings as found. Every beam of such a plane runs
  /// ahead cot(pitch) per unit of drop, whatever its angle in the scan, so
  /// a reading's along-track place at the top's level follows from its
  /// height alone. The far side's readings (a face the beams cannot meet)
  /// lie on the last scans that crossed the top, spread up and down their
  /// beams by range noise, by mixed pixels between the edge and the floor
  /// behind it, and by eq. (10) keeping the highest; moved back along their
  /// beams to the top's level they fall on the lines where those scans
  /// crossed it, and that side takes its edge from them (fit_box_edges's
  /// `beam_level_readings`). The near side keeps its readings: those on the
  /// face the beams met are at the edge whatever their height, and moved to
  /// the top's level they would leave it by their depth on the face times
  /// cot(pitch).
  double sensor_pitch_rad = std::numeric_limits<double>::quiet_NaN();
  /// The top's level for that move, in robust standard deviations (1.4826 x
  /// the median absolute deviation) of the top's cells below their median:
  /// each cell holds its highest reading, so the surface lies below them.
  /// Tuned on seeds 1 and 2 of the URG fidelity run (2 and 3 did about as
  /// well; docs/experiments.md).
  double level_below_top_sds = 2.5;
  /// Grow the region through measured cells only, not filled ones: the fill
  /// (eq. 11) spans a shadowed gap between two tall objects at their height
  /// and would join them. Only where the tops are measured throughout (a
  /// sweep no coarser than the grid): with cells finer than the sweep, the
  /// fill closes the rows between scans and a top would fall apart.
  bool region_measured_only = false;
  /// The sweep's step along travel_heading_rad [m] for a sensor that never
  /// lights a far side (structured light: the sheet leaves a top for the
  /// floor beyond it); NaN (the default): sides as read. The top is read up
  /// to its last frame's stripe on it, anywhere within a step before the
  /// edge; a far side running less than a step along the travel direction
  /// is placed at the middle of the part left unread, half a step out when
  /// square to it (set by the cart rail for structured light).
  double unlit_far_side_step_m = std::numeric_limits<double>::quiet_NaN();
  BoxEdgeOptions edges{};
};

/// For each object: the connected region of known (or, with
/// region_measured_only, measured) cells higher than half
/// way between the local ground and the top at the object's centre, grown
/// from the cell nearest that centre. The scene's truth says only which
/// object is which (its centre seeds the region, its length names the
/// measured axis nearer its own): the region is not clipped to the true
/// footprint and its axes are the minimum-area rectangle of its cells, not
/// the true yaw. The sub-cell edges come from the readings of the region's
/// border cells (their top-point layers), sorted to the sides of the
/// cells' rectangle; nothing of the truth enters them. Height is the median of the region's measured elevations
/// above the median of a ring of cells around it.
/// Validates `options` first (validate).
std::vector<ObjectMeasurement> measure_objects(const MapSnapshot& snapshot, const Scene& scene,
                                               const ObjectMeasureOptions& options = {});

/// Throws InputError when an option is out of range: sensor_pitch_rad
/// neither NaN nor in (0, pi/2); level_below_top_sds not finite or negative;
/// unlit_far_side_step_m neither NaN nor in (0, 1) m.
void validate(const ObjectMeasureOptions& options);

/// Relative error in per cent, (measured - truth) / truth * 100.
double relative_error_pct(double measured, double truth);

}  // namespace stridemap
