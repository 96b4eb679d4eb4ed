#pragma once
// Hokuyo URG-04LX sensor model: beam geometry from the parameters the sensor
// reports (SCIP "PP"), validity of raw values, the spec's range uncertainty,
// and conversion of raw millimetre values into a PlanarScan.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "stridemap/core/planar_beams.hpp"
#include "stridemap/core/planar_scan.hpp"
#include "stridemap/sensors/range_calibration.hpp"

namespace stridemap {

/// Geometry and limits as the sensor reports them (PP reply). Defaults are a
/// URG-04LX: steps 44..725 of 1024 per turn, front at step 384, 10 Hz.
struct UrgParameters {
  int first_step = 44;        ///< AMIN: first measurable step
  int last_step = 725;        ///< AMAX: last measurable step (682 beams in all)
  int front_step = 384;       ///< AFRT: step pointing straight ahead
  int steps_per_turn = 1024;  ///< ARES: angular resolution, steps per 360 deg
  double min_range_m = 0.020; ///< DMIN: raw values below this are error codes
  double max_range_m = 5.600; ///< DMAX: raw values above this are invalid
  double scan_period_s = 0.1; ///< 60 / SCAN (600 rpm)

  /// Throws InputError naming the offending field when the set is inconsistent.
  void validate() const;
  /// Number of beams between first_step and last_step inclusive.
  int beam_count() const { return last_step - first_step + 1; }
  /// Beam direction of a step: (step - front_step) * 2 pi / steps_per_turn,
  /// positive to the left (the URG turns counter-clockwise seen from above).
  double step_angle_rad(double step) const;
};

/// One scan as it comes off the wire: raw values in millimetres, error codes
/// (values below DMIN) kept.
struct UrgRawScan {
  double time_s = 0.0;
  int first_step = 44;  ///< step of values_mm[0]
  int cluster = 1;      ///< steps merged per value (SCIP cluster count, >= 1)
  std::vector<std::uint32_t> values_mm;
};

/// How a raw value was classified.
enum class UrgValueClass : std::uint8_t { valid, error_code, beyond_max_range };

struct UrgConversionStats {
  std::size_t valid = 0;
  std::size_t error_codes = 0;       ///< raw value below DMIN (sensor error code)
  std::size_t beyond_max_range = 0;  ///< raw value above DMAX

  UrgConversionStats& operator+=(const UrgConversionStats& other) {
    valid += other.valid;
    error_codes += other.error_codes;
    beyond_max_range += other.beyond_max_range;
    return *this;
  }
};

class UrgModel {
 public:
  explicit UrgModel(const UrgParameters& parameters = {}, const RangeCalibration& calibration = {});

  const UrgParameters& parameters() const { return parameters_; }
  const RangeCalibration& calibration() const { return calibration_; }

  UrgValueClass classify(std::uint32_t raw_mm) const;

  /// Manufacturer's accuracy bound for a white target: 10 mm up to 1 m, 1 % of
  /// the range beyond (the spec states it to 4 m; it is extrapolated beyond).
  static double spec_range_error_m(double range_m);

  /// Converts raw values to ranges in metres (calibrated), beam angles and
  /// Delta r. Invalid values become NaN; their range_error_m holds the spec
  /// bound at the raw value, so it is finite for every beam. Reuses out's
  /// storage. Throws InputError if the raw scan's first step, cluster or
  /// length do not fit the parameters (names the field and the numbers).
  UrgConversionStats to_planar_scan(const UrgRawScan& raw, PlanarScan& out) const;
  /// The same conversion straight into the mapper's packed beams
  /// (TerrainMapper::integrate(PlanarBeams)): only the beams the mapper
  /// would use, with the cosine and sine of their angles from a table made
  /// once. The map is the one to_planar_scan + integrate(PlanarScan) make,
  /// bit for bit. Throws InputError as to_planar_scan does.
  UrgConversionStats to_beams(const UrgRawScan& raw, PlanarBeams& out) const;
  /// Throws the InputError the conversions would for `raw`, converting
  /// nothing: for a caller that must refuse a scan the pipeline would only count.
  void check_fits(const UrgRawScan& raw) const;

 private:
  template <bool kCalibrated>
  UrgConversionStats pack_beams(const UrgRawScan& raw, PlanarBeams& out) const;

  UrgParameters parameters_;
  RangeCalibration calibration_;
  // Per measurable step (index step - first_step): its angle, and that
  // angle's cosine and sine.
  std::vector<double> step_angle_, step_cos_, step_sin_;
  // classify() as whole millimetres: a raw value is valid when it lies in
  // [lowest_valid_mm_, highest_valid_mm_] (empty when lowest > highest).
  std::uint64_t lowest_valid_mm_ = 0, highest_valid_mm_ = 0;
  bool calibrated_ = false;  // any coefficient non-zero
};

}  // namespace stridemap
