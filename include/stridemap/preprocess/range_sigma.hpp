#pragma once
// How the filters turn a beam into a range standard deviation sigma_r. The
// scan carries each beam's maximum error Delta r (eq. 6); the filters need a
// standard deviation, so the relation between the two is an explicit option.
#include <cmath>

namespace stridemap {

struct RangeSigmaModel {
  /// sigma_r = sigma_per_range_error * Delta r. Delta r is a maximum error;
  /// reading it as a 3-sigma bound gives 1/3, so that a "3 sigma" tolerance
  /// equals Delta r itself (for the URG-04LX: 10 mm up to 1 m). MessorSim uses
  /// the spec bound as sigma, i.e. 1.0 (algorithms.md 2.2, 5.6).
  double sigma_per_range_error = 1.0 / 3.0;
  /// Ignore the scan's range_error_m and always take Delta r from the URG-04LX
  /// specification (10 mm up to 1 m, 1 % of the range beyond). The spec is also
  /// used for any beam whose range_error_m is not finite and positive.
  bool always_use_urg_spec = false;

  /// sigma_r [m] of a valid beam.
  double sigma_m(double range_m, double range_error_m) const {
    if (always_use_urg_spec || !(std::isfinite(range_error_m) && range_error_m > 0.0)) {
      return sigma_per_range_error * urg_spec_range_error_m(range_m);
    }
    return sigma_per_range_error * range_error_m;
  }

  /// Throws InputError naming `owner` and the field when an option is unusable.
  void validate(const char* owner) const;

 private:
  static double urg_spec_range_error_m(double range_m);  // UrgModel::spec_range_error_m
};

}  // namespace stridemap
