#include "stridemap/sensors/urg04lx.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <numbers>
#include <sstream>
#include <string>
#include <type_traits>

#if defined(__x86_64__)
#include <immintrin.h>

#include "stridemap/core/detail/kept_lanes_avx2.hpp"
#endif

#include "stridemap/core/error.hpp"

namespace stridemap {
namespace {

[[noreturn]] void throw_parameter_error(const std::string& field, const std::string& what) {
  throw InputError("URG parameters: " + field + " " + what);
}

void require_finite(const char* field, double value) {
  if (!std::isfinite(value)) {
    std::ostringstream message;
    message << "must be finite, got " << value;
    throw_parameter_error(field, message.str());
  }
}

// The sensor reports DMIN/DMAX in whole millimetres; a parameter set written
// in metres may carry representation error (0.020 * 1000 need not be exactly
// 20), so the thresholds get a margin far below one raw unit.
constexpr double threshold_margin_mm = 1e-6;

}  // namespace

void UrgParameters::validate() const {
  auto describe = [](const char* relation, long long value, long long bound) {
    std::ostringstream message;
    message << "must be " << relation << " " << bound << ", got " << value;
    return message.str();
  };
  if (steps_per_turn <= 0) {
    throw_parameter_error("steps_per_turn", describe(">", steps_per_turn, 0));
  }
  if (first_step < 0) throw_parameter_error("first_step", describe(">=", first_step, 0));
  if (front_step < first_step) {
    throw_parameter_error("front_step", describe(">= first_step =", front_step, first_step));
  }
  if (last_step < front_step) {
    throw_parameter_error("last_step", describe(">= front_step =", last_step, front_step));
  }
  if (last_step >= steps_per_turn) {
    throw_parameter_error("last_step", describe("< steps_per_turn =", last_step, steps_per_turn));
  }
  // The scan commands (GD, MD) name steps in four digits, so no scan reaches
  // beyond; the model's beam tables are sized by last_step - first_step.
  constexpr long long kMaxStep = 9999;
  if (last_step > kMaxStep) throw_parameter_error("last_step", describe("<=", last_step, kMaxStep));
  require_finite("min_range_m", min_range_m);
  require_finite("max_range_m", max_range_m);
  require_finite("scan_period_s", scan_period_s);
  if (!(min_range_m > 0.0)) {
    std::ostringstream message;
    message << "must be > 0, got " << min_range_m;
    throw_parameter_error("min_range_m", message.str());
  }
  if (!(max_range_m > min_range_m)) {
    std::ostringstream message;
    message << "must be > min_range_m = " << min_range_m << ", got " << max_range_m;
    throw_parameter_error("max_range_m", message.str());
  }
  if (!(scan_period_s > 0.0)) {
    std::ostringstream message;
    message << "must be > 0, got " << scan_period_s;
    throw_parameter_error("scan_period_s", message.str());
  }
}

double UrgParameters::step_angle_rad(double step) const {
  return (step - static_cast<double>(front_step)) * (2.0 * std::numbers::pi) /
         static_cast<double>(steps_per_turn);
}

UrgModel::UrgModel(const UrgParameters& parameters, const RangeCalibration& calibration)
    : parameters_(parameters), calibration_(calibration) {
  parameters_.validate();
  for (std::size_t k = 0; k < calibration_.coefficients.size(); ++k) {
    if (!std::isfinite(calibration_.coefficients[k])) {
      std::ostringstream message;
      message << "range calibration: coefficients[" << k << "] must be finite, got "
              << calibration_.coefficients[k];
      throw InputError(message.str());
    }
    // With every coefficient zero, raw + correction(raw) is raw exactly.
    if (calibration_.coefficients[k] != 0.0) calibrated_ = true;
  }
  const auto steps = static_cast<std::size_t>(parameters_.beam_count());
  step_angle_.resize(steps);
  step_cos_.resize(steps);
  step_sin_.resize(steps);
  for (std::size_t k = 0; k < steps; ++k) {
    step_angle_[k] = parameters_.step_angle_rad(static_cast<double>(parameters_.first_step) + static_cast<double>(k));
    step_cos_[k] = std::cos(step_angle_[k]);
    step_sin_[k] = std::sin(step_angle_[k]);
  }
  // classify() compares a whole number v with a double bound A: v < A holds
  // exactly when v < ceil(A), and v > B exactly when v > floor(B).
  constexpr double kTop = 4294967295.0;  // largest raw value
  const double lowest = std::ceil(parameters_.min_range_m * 1000.0 - threshold_margin_mm);
  const double highest = std::floor(parameters_.max_range_m * 1000.0 + threshold_margin_mm);
  lowest_valid_mm_ = lowest <= 0.0 ? 0 : lowest > kTop ? std::uint64_t{1} << 32 : static_cast<std::uint64_t>(lowest);
  highest_valid_mm_ = highest >= kTop ? static_cast<std::uint64_t>(kTop) : static_cast<std::uint64_t>(highest);
}

UrgValueClass UrgModel::classify(std::uint32_t raw_mm) const {
  if (raw_mm < lowest_valid_mm_) return UrgValueClass::error_code;
  if (raw_mm > highest_valid_mm_) return UrgValueClass::beyond_max_range;
  return UrgValueClass::valid;
}

double UrgModel::spec_range_error_m(double range_m) {
  // NaN falls through the comparison and comes back as NaN: a bound for an
  // unknown range would be made up.
  if (range_m <= 1.0) return 0.010;
  return 0.01 * range_m;
}

void UrgModel::check_fits(const UrgRawScan& raw) const {
  const long long count = static_cast<long long>(raw.values_mm.size());
  if (raw.cluster < 1) {
    std::ostringstream message;
    message << "URG scan at t=" << raw.time_s << " s: cluster must be >= 1, got " << raw.cluster;
    throw InputError(message.str());
  }
  if (raw.first_step < parameters_.first_step || raw.first_step > parameters_.last_step) {
    std::ostringstream message;
    message << "URG scan at t=" << raw.time_s << " s: first_step " << raw.first_step
            << " lies outside the measurable steps " << parameters_.first_step << ".."
            << parameters_.last_step;
    throw InputError(message.str());
  }
  if (count > 0) {
    // The sensor sends ceil(steps / cluster) values, so only the first step of
    // the last cluster has to be measurable; the cluster may run past it.
    const long long last_value_step =
        static_cast<long long>(raw.first_step) + (count - 1) * static_cast<long long>(raw.cluster);
    if (last_value_step > parameters_.last_step) {
      std::ostringstream message;
      message << "URG scan at t=" << raw.time_s << " s: " << count << " values with first_step "
              << raw.first_step << " and cluster " << raw.cluster << " reach step "
              << last_value_step << ", beyond last_step " << parameters_.last_step
              << " (at most "
              << (parameters_.last_step - raw.first_step) / raw.cluster + 1 << " values fit)";
      throw InputError(message.str());
    }
  }
}

// STRIDEMAP_NO_AVX2_COPIES: the scalar loop only (to test it on an AVX2 CPU).
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && defined(__linux__) && \
    !defined(STRIDEMAP_NO_AVX2_COPIES)
#define STRIDEMAP_URG_AVX2 1
namespace {
// Raw values [mm] -> doubles, exactly: flip the sign bit, convert as
// int32, add 2^31 (AVX2 has no unsigned conversion).
__attribute__((target("avx2"))) inline __m256d values_as_doubles(const std::uint32_t* values) {
  const __m128i sign = _mm_set1_epi32(static_cast<int>(0x80000000u));
  const __m128i v = _mm_xor_si128(_mm_loadu_si128(reinterpret_cast<const __m128i*>(values)), sign);
  return _mm256_add_pd(_mm256_cvtepi32_pd(v), _mm256_set1_pd(2147483648.0));
}

// raw + (c0 + raw (c1 + raw (c2 + raw c3))), as the scalar loop.
__attribute__((target("avx2"))) inline __m256d calibrated(__m256d raw_m, const double* c) {
  __m256d poly = _mm256_mul_pd(raw_m, _mm256_set1_pd(c[3]));
  poly = _mm256_mul_pd(raw_m, _mm256_add_pd(_mm256_set1_pd(c[2]), poly));
  poly = _mm256_mul_pd(raw_m, _mm256_add_pd(_mm256_set1_pd(c[1]), poly));
  return _mm256_add_pd(raw_m, _mm256_add_pd(_mm256_set1_pd(c[0]), poly));
}

// The four 64-bit lane counts of a vector, added.
__attribute__((target("avx2"))) inline std::size_t lane_total(__m256i counts) {
  alignas(32) std::uint64_t lanes[4];
  _mm256_store_si256(reinterpret_cast<__m256i*>(lanes), counts);
  return static_cast<std::size_t>(lanes[0] + lanes[1] + lanes[2] + lanes[3]);
}

// pack_beams' loop four beams at a time where the CPU has AVX2 (chosen at
// run time; x86-64's baseline has no blend and no lane permute). The same
// operations in the same order as the scalar loop, without FMA, so every
// kept beam is the scalar loop's bit for bit; the kept lanes are moved to
// the front by one permute per array and stored at `count` (the lanes
// beyond are overwritten by the next block or left beyond out.count).
// Returns the beams consumed (a multiple of 4); the caller finishes the rest.
template <bool kCalibrated, bool kZeroInRange>
__attribute__((target("avx2"))) std::size_t pack_blocks_avx2(const std::uint32_t* values, std::size_t n,
                                                              const double* cos_t, const double* sin_t,
                                                              double lowest, double highest, const double* c,
                                                              double* range, double* error, double* out_cos,
                                                              double* out_sin, std::size_t& count, std::size_t& valid,
                                                              std::size_t& beyond) {
  const __m256d lo = _mm256_set1_pd(lowest), hi = _mm256_set1_pd(highest);
  const __m256d milli = _mm256_set1_pd(0.001), centi = _mm256_set1_pd(0.01);
  [[maybe_unused]] const __m256d zero = _mm256_setzero_pd();
  const __m256d inf = _mm256_set1_pd(std::numeric_limits<double>::infinity());
  // The valid and beyond counts per lane: a true compare is all ones (-1 as
  // an int64), so subtracting it counts one.
  __m256i valid_lanes = _mm256_setzero_si256(), beyond_lanes = _mm256_setzero_si256();
  std::size_t i = 0;
  for (; i + 4 <= n; i += 4) {
    const __m256d value = values_as_doubles(values + i);
    const __m256d in_range = _mm256_and_pd(_mm256_cmp_pd(value, lo, _CMP_GE_OQ), _mm256_cmp_pd(value, hi, _CMP_LE_OQ));
    valid_lanes = _mm256_sub_epi64(valid_lanes, _mm256_castpd_si256(in_range));
    beyond_lanes = _mm256_sub_epi64(beyond_lanes, _mm256_castpd_si256(_mm256_cmp_pd(value, hi, _CMP_GT_OQ)));
    if (_mm256_testz_pd(in_range, in_range)) continue;  // no lane in range
    const __m256d raw_m = _mm256_mul_pd(value, milli);
    __m256d r = raw_m;
    __m256d keep = in_range;
    if constexpr (kCalibrated) {
      r = calibrated(raw_m, c);
      keep = _mm256_and_pd(keep, _mm256_and_pd(_mm256_cmp_pd(r, zero, _CMP_GT_OQ), _mm256_cmp_pd(r, inf, _CMP_LT_OQ)));
    } else if constexpr (kZeroInRange) {
      keep = _mm256_and_pd(keep, _mm256_cmp_pd(value, zero, _CMP_NEQ_OQ));
    }  // else a value in range is at least DMIN >= 1: never 0
    const auto mask = static_cast<unsigned>(_mm256_movemask_pd(keep));
    // max(0.01, 0.01 r) as the scalar loop's std::max (r is finite here).
    const __m256d err = _mm256_max_pd(centi, _mm256_mul_pd(centi, r));
    detail::store_kept_lanes(mask, r, err, _mm256_loadu_pd(cos_t + i), _mm256_loadu_pd(sin_t + i), range, error, out_cos,
                             out_sin, count);
  }
  valid += lane_total(valid_lanes);
  beyond += lane_total(beyond_lanes);
  return i;
}

// to_planar_scan's loop four beams at a time, as pack_blocks_avx2 is
// pack_beams': the same operations in the same order, selects as blends.
// The caller copies the angles and finishes the rest.
template <bool kCalibrated>
__attribute__((target("avx2"))) std::size_t planar_blocks_avx2(const std::uint32_t* values, std::size_t n,
                                                                double lowest, double highest, const double* c,
                                                                double* range, double* error, std::size_t& valid,
                                                                std::size_t& below) {
  const __m256d lo = _mm256_set1_pd(lowest), hi = _mm256_set1_pd(highest);
  const __m256d milli = _mm256_set1_pd(0.001), centi = _mm256_set1_pd(0.01), one = _mm256_set1_pd(1.0);
  const __m256d nan = _mm256_set1_pd(std::numeric_limits<double>::quiet_NaN());
  __m256i valid_lanes = _mm256_setzero_si256(), below_lanes = _mm256_setzero_si256();
  std::size_t i = 0;
  for (; i + 4 <= n; i += 4) {
    const __m256d value = values_as_doubles(values + i);
    const __m256d in_range = _mm256_and_pd(_mm256_cmp_pd(value, lo, _CMP_GE_OQ), _mm256_cmp_pd(value, hi, _CMP_LE_OQ));
    valid_lanes = _mm256_sub_epi64(valid_lanes, _mm256_castpd_si256(in_range));
    below_lanes = _mm256_sub_epi64(below_lanes, _mm256_castpd_si256(_mm256_cmp_pd(value, lo, _CMP_LT_OQ)));
    const __m256d raw_m = _mm256_mul_pd(value, milli);
    __m256d r = raw_m;
    if constexpr (kCalibrated) r = calibrated(raw_m, c);
    const __m256d bounded = _mm256_blendv_pd(raw_m, r, in_range);
    _mm256_storeu_pd(range + i, _mm256_blendv_pd(nan, r, in_range));
    _mm256_storeu_pd(error + i, _mm256_blendv_pd(_mm256_mul_pd(centi, bounded), centi,
                                                 _mm256_cmp_pd(bounded, one, _CMP_LE_OQ)));
  }
  valid += lane_total(valid_lanes);
  below += lane_total(below_lanes);
  return i;
}
}  // namespace
#endif

UrgConversionStats UrgModel::to_planar_scan(const UrgRawScan& raw, PlanarScan& out) const {
  check_fits(raw);
  out.time_s = raw.time_s;
  const std::size_t n = raw.values_mm.size();
  out.resize(n);
  // check_fits() keeps every value's step within the table. A cluster's
  // value is the minimum over its steps and the sensor does not say which
  // step gave it; SCIP drivers place it at the cluster's first step.
  const auto first = static_cast<std::size_t>(raw.first_step - parameters_.first_step);
  const auto cluster = static_cast<std::size_t>(raw.cluster);
  const std::uint32_t* values = raw.values_mm.data();
  const double* step_angle = step_angle_.data() + first;
  double* angle = out.angle_rad.data();
  double* range = out.range_m.data();
  double* error = out.range_error_m.data();
  const std::uint64_t lowest = lowest_valid_mm_, highest = highest_valid_mm_;
  const auto& c = calibration_.coefficients;
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  std::size_t valid = 0, below = 0;
  // classify(), calibration_.corrected_m() and spec_range_error_m() as
  // selects instead of branches (the same doubles), so that the error codes
  // between valid runs cost no mispredictions. Uncalibrated, the correction
  // is raw * 0 + 0: the raw range itself. Invalid beams keep a finite error
  // (the bound at the raw value) so that a consumer summing or comparing
  // errors never meets NaN there; the NaN range marks the beam as unusable.
  const auto convert = [&](auto calibrated) {
    std::size_t i = 0;
#ifdef STRIDEMAP_URG_AVX2
    // Beams at consecutive steps: the angles are the table's, the rest four
    // a vector (thresholds as doubles, exact: both below 2^33).
    static const bool has_avx2 = __builtin_cpu_supports("avx2");
    if (has_avx2 && cluster == 1) {
      if (n > 0) std::memcpy(angle, step_angle, n * sizeof(double));
      i = planar_blocks_avx2<decltype(calibrated)::value>(values, n, static_cast<double>(lowest),
                                                          static_cast<double>(highest), c.data(), range, error, valid,
                                                          below);
    }
#endif
    for (; i < n; ++i) {
      const std::uint64_t value = values[i];
      const double raw_range_m = static_cast<double>(values[i]) * 0.001;
      double range_m = raw_range_m;
      if constexpr (decltype(calibrated)::value) {
        range_m = raw_range_m + (c[0] + raw_range_m * (c[1] + raw_range_m * (c[2] + raw_range_m * c[3])));
      }
      const bool is_valid = (value >= lowest) & (value <= highest);
      const double bounded_m = is_valid ? range_m : raw_range_m;
      angle[i] = step_angle[i * cluster];
      range[i] = is_valid ? range_m : kNaN;
      error[i] = bounded_m <= 1.0 ? 0.010 : 0.01 * bounded_m;
      valid += static_cast<std::size_t>(is_valid);
      below += static_cast<std::size_t>(value < lowest);
    }
  };
  if (calibrated_) {
    convert(std::true_type{});
  } else {
    convert(std::false_type{});
  }
  UrgConversionStats stats;
  stats.valid = valid;
  stats.error_codes = below;
  stats.beyond_max_range = n - valid - below;
  return stats;
}

template <bool kCalibrated>
UrgConversionStats UrgModel::pack_beams(const UrgRawScan& raw, PlanarBeams& out) const {
  const std::size_t n = raw.values_mm.size();
  out.prepare(n);
  out.time_s = raw.time_s;
  const std::uint32_t* values = raw.values_mm.data();
  const auto first = static_cast<std::size_t>(raw.first_step - parameters_.first_step);
  const double* cos_t = step_cos_.data() + first;
  const double* sin_t = step_sin_.data() + first;
  const auto cluster = static_cast<std::size_t>(raw.cluster);
  double* range = out.range_m.data();
  double* error = out.range_error_m.data();
  double* out_cos = out.cos_angle.data();
  double* out_sin = out.sin_angle.data();
  const std::uint64_t lowest = lowest_valid_mm_, highest = highest_valid_mm_;
  // valid <=> value - lowest <= span, in one unsigned comparison.
  const std::uint64_t span = highest >= lowest ? highest - lowest : 0;
  const bool any_valid = highest >= lowest;
  const auto& c = calibration_.coefficients;
  constexpr double kInf = std::numeric_limits<double>::infinity();
  std::size_t count = 0, beyond = 0, valid = 0;
  if (!any_valid) {  // DMIN above DMAX (a made-up sensor): nothing is valid
    for (std::size_t i = 0; i < n; ++i) beyond += static_cast<std::size_t>(values[i] > highest);
  }
  const std::size_t scanned = any_valid ? n : 0;
  std::size_t i = 0;
#ifdef STRIDEMAP_URG_AVX2
  // The blocks need each beam's own direction next to the last (no
  // clusters) and the thresholds as doubles (exact: both below 2^33).
  static const bool has_avx2 = __builtin_cpu_supports("avx2");
  if (has_avx2 && cluster == 1 && any_valid) {
    const auto lowest_mm = static_cast<double>(lowest), highest_mm = static_cast<double>(highest);
    i = lowest == 0 ? pack_blocks_avx2<kCalibrated, true>(values, n, cos_t, sin_t, lowest_mm, highest_mm, c.data(), range,
                                                          error, out_cos, out_sin, count, valid, beyond)
                    : pack_blocks_avx2<kCalibrated, false>(values, n, cos_t, sin_t, lowest_mm, highest_mm, c.data(),
                                                           range, error, out_cos, out_sin, count, valid, beyond);
  }
#endif
  // Valid and invalid values come in long runs (ground, then sky), so the
  // branch is well predicted. A beam is kept when the mapper would use it
  // from to_planar_scan: a valid value whose calibrated range is finite and
  // positive (its error, 1 cm or 1 %, and its angle are then finite too).
  for (; i < scanned; ++i) {
    const std::uint64_t value = values[i];
    if (value - lowest > span) {
      beyond += static_cast<std::size_t>(value > highest);
      continue;
    }
    ++valid;
    const double raw_m = static_cast<double>(static_cast<std::int64_t>(value)) * 0.001;
    double r = raw_m;
    if constexpr (kCalibrated) {
      r = raw_m + (c[0] + raw_m * (c[1] + raw_m * (c[2] + raw_m * c[3])));
      if (!(r > 0.0 && r < kInf)) continue;
    } else if (value == 0) {
      continue;  // a DMIN below 1 mm lets 0 through; the mapper takes no zero range
    }
    const std::size_t step = i * cluster;
    range[count] = r;
    // spec_range_error_m (1 cm up to 1 m, then 1 %) as a max: for a finite
    // r > 0, 0.01 r rounds to at most 0.01 exactly when r <= 1.
    error[count] = std::max(0.010, 0.01 * r);
    out_cos[count] = cos_t[step];
    out_sin[count] = sin_t[step];
    ++count;
  }
  out.count = count;
  out.invalid_range = n - count;  // an error code, beyond DMAX or calibrated out of range
  UrgConversionStats stats;
  stats.valid = valid;
  stats.beyond_max_range = beyond;
  stats.error_codes = n - valid - beyond;
  return stats;
}

UrgConversionStats UrgModel::to_beams(const UrgRawScan& raw, PlanarBeams& out) const {
  check_fits(raw);
  return calibrated_ ? pack_beams<true>(raw, out) : pack_beams<false>(raw, out);
}

}  // namespace stridemap
