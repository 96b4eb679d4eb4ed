#include "stridemap/preprocess/range_sigma.hpp"

#include <cmath>
#include <string>

#include "stridemap/core/error.hpp"
#include "stridemap/sensors/urg04lx.hpp"

namespace stridemap {

double RangeSigmaModel::sigma_m(double range_m, double range_error_m) const {
  double max_error_m = range_error_m;
  if (always_use_urg_spec || !(std::isfinite(max_error_m) && max_error_m > 0.0)) {
    max_error_m = UrgModel::spec_range_error_m(range_m);
  }
  return sigma_per_range_error * max_error_m;
}

void RangeSigmaModel::validate(const char* owner) const {
  if (!(std::isfinite(sigma_per_range_error) && sigma_per_range_error > 0.0)) {
    throw InputError(std::string(owner) + ": sigma.sigma_per_range_error is " +
                     std::to_string(sigma_per_range_error) + "; it must be finite and positive");
  }
}

}  // namespace stridemap
