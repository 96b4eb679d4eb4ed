#pragma once
// The update rule of section 5.2: the predicted maximum elevation change
// Delta z_max (eq. 6 with gamma of eq. 7 and the turning extension of
// Fig. 10), then certainty (eq. 9) and elevation (eq. 10) of one cell.
#include <cmath>
#include <cstdint>
#include <numbers>

#include "stridemap/core/enum_names.hpp"
#include "stridemap/core/grid_map.hpp"
#include "stridemap/core/sensor_transform.hpp"

namespace stridemap {

inline constexpr double kDegToRad = std::numbers::pi / 180.0;

/// What a reading that disagrees with a known cell does to its elevation.
enum class ElevationRule : std::uint8_t {
  /// Eq. (10) as printed: the highest reading always wins, plausible or not.
  paper_highest,
  /// A reading outside Delta z_max changes nothing at once; after
  /// `replace_after_contradictions` such readings with no plausible one in
  /// between, the cell takes the highest of them and restarts its certainty.
  /// A single stray point (range noise pushing a point off an edge into the
  /// next cell, a spike) then cannot raise a cell that many readings agree
  /// on, while a real change still wins within a few scans. Readings within
  /// the bound keep eq. (9)/(10) unchanged, so a face climbed by the tilted
  /// scan plane (d tan gamma per scan) rises as before.
  gated_highest,
};

inline constexpr EnumNameTable<ElevationRule, 2> kElevationRuleNames{{
    {ElevationRule::paper_highest, "paper"},
    {ElevationRule::gated_highest, "gated"},
}};
/// "paper" or "gated": the word in configs, options and summary.json.
constexpr std::string_view name(ElevationRule rule) { return enum_name_in(kElevationRuleNames, rule); }
template <>
inline ElevationRule parse_enum_name<ElevationRule>(std::string_view text) {
  return enum_value_in(kElevationRuleNames, text, "an elevation rule");
}

struct UpdateOptions {
  /// a of eq. (9): certainty gained by one plausible measurement. The
  /// authors' implementation uses 3.
  double certainty_increment = 3.0;
  /// Certainty stops growing here, so that a long-observed cell can still be
  /// corrected in finite time. The authors' implementation caps at 100.
  double certainty_max = 100.0;
  /// Delta phi_r: maximum error of the trunk pitch estimate (IMU) [rad].
  double max_pitch_error_rad = 1.0 * kDegToRad;
  /// Delta psi_r: maximum error of the trunk roll estimate (IMU) [rad].
  double max_roll_error_rad = 1.0 * kDegToRad;
  /// Delta alpha: maximum error of the sensor's mounting pitch [rad]; the
  /// paper uses 1 deg.
  double max_mount_pitch_error_rad = 1.0 * kDegToRad;
  /// Add the horizontal travel caused by turning (Fig. 10) to d_(k,k+1).
  bool use_turning_term = true;
  /// Eq. (10) as printed by default; see ElevationRule.
  ElevationRule elevation_rule = ElevationRule::paper_highest;
  /// For gated_highest: contradicting readings in a row that replace the
  /// cell (1..255).
  int replace_after_contradictions = 3;
};

/// The motion between the previous scan and this one, as eq. (6) needs it.
struct ScanMotion {
  double horizontal_travel_m = 0.0;  ///< sensor travel in the horizontal plane [m]
  double yaw_change_rad = 0.0;       ///< theta of Fig. 10 [rad]
};

/// Fig. 10: the extra horizontal travel d = Delta x tan(theta) for a point at
/// horizontal distance r ahead of a sensor d_s from the turning centre, with
/// Delta x = (r + d_s) tan(theta/2) sgn(theta). Returned as a magnitude.
double turning_travel_m(double point_distance_m, double sensor_turn_offset_m, double yaw_change_rad);

/// The error part of eq. (6): |dz/dr| Dr + |dz/dpsi| Dpsi + |dz/dphi| Dphi +
/// |dz/dalpha| Dalpha, worst-case magnitudes added up.
inline double elevation_error_bound_m(const ElevationPartials& p, double range_error_m, const UpdateOptions& o) {
  const auto mag = [](double v) { return v < 0 ? -v : v; };
  return mag(p.d_range * range_error_m) + mag(p.d_roll_m_per_rad) * o.max_roll_error_rad +
         mag(p.d_pitch_m_per_rad) * o.max_pitch_error_rad + mag(p.d_alpha_m_per_rad) * o.max_mount_pitch_error_rad;
}

/// Eq. (6): d tan(gamma) + |dz/dr| Dr + |dz/dpsi| Dpsi + |dz/dphi| Dphi +
/// |dz/dalpha| Dalpha. All terms are worst-case magnitudes.
double laser_max_elevation_change(const ElevationPartials& partials, double range_error_m,
                                  double travel_m, double gamma_rad, const UpdateOptions& options);

/// What eq. (9)/(10) did to one cell.
enum class CellUpdate : std::uint8_t {
  first = 0,        ///< the cell was unknown; it takes the measurement
  plausible = 1,    ///< |h_m - h| <= |Delta z_max|: certainty raised
  implausible = 2,  ///< outside the bound: certainty kept
  replaced = 3,     ///< gated rule: enough contradictions replaced the cell
};

/// One cell's storage, as ElevationMap lays it out.
struct CellRef {
  float& elevation;
  float& certainty;
  std::uint8_t& state;
  float& pending_elevation;
  std::uint8_t& contradictions;
  float& mean_elevation;
  std::uint16_t& mean_count;
};

/// Adds an accepted reading to the cell's running mean (ElevationMap::
/// mean_elevation); the count saturates, after which the mean keeps moving
/// with weight 1/65535.
inline void add_to_mean(CellRef cell, float h_m) {
  cell.mean_count = static_cast<std::uint16_t>(cell.mean_count + (cell.mean_count < 0xFFFF ? 1 : 0));  // no branch
  cell.mean_elevation += (h_m - cell.mean_elevation) / static_cast<float>(cell.mean_count);
}

/// Eq. (9) then eq. (10) (or the gated rule) on one cell. An unknown or
/// filled cell takes the measurement as it is.
inline CellUpdate update_cell(CellRef cell, float h_m, float dz_max, const UpdateOptions& options) {
  const auto a = static_cast<float>(options.certainty_increment);
  const auto ceiling = static_cast<float>(options.certainty_max);
  if (cell.state != static_cast<std::uint8_t>(CellState::measured)) {
    cell.elevation = h_m;
    cell.certainty = a < ceiling ? a : ceiling;
    cell.state = static_cast<std::uint8_t>(CellState::measured);
    cell.contradictions = 0;
    cell.mean_elevation = h_m;
    cell.mean_count = 1;
    return CellUpdate::first;
  }
  const float difference = h_m - cell.elevation;
  // fabs differs from v < 0 ? -v : v only in the sign of a zero, which a
  // comparison does not see; it is one instruction, not a branch.
  const bool plausible = std::fabs(difference) <= std::fabs(dz_max);
  if (plausible) {
    const float raised = cell.certainty + a;
    cell.certainty = raised > ceiling ? ceiling : raised;
    if (h_m > cell.elevation) cell.elevation = h_m;
    cell.contradictions = 0;
    add_to_mean(cell, h_m);
    return CellUpdate::plausible;
  }
  if (options.elevation_rule == ElevationRule::paper_highest) {
    if (h_m > cell.elevation) cell.elevation = h_m;
    return CellUpdate::implausible;
  }
  cell.pending_elevation = cell.contradictions == 0 || h_m > cell.pending_elevation ? h_m : cell.pending_elevation;
  ++cell.contradictions;
  if (cell.contradictions < options.replace_after_contradictions) return CellUpdate::implausible;
  cell.elevation = cell.pending_elevation;
  cell.certainty = a < ceiling ? a : ceiling;
  cell.contradictions = 0;
  cell.mean_elevation = cell.pending_elevation;
  cell.mean_count = 1;
  return CellUpdate::replaced;
}

}  // namespace stridemap
