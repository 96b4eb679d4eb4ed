#include "stridemap/preprocess/range_sigma.hpp"

#include <cmath>
#include <string>

#include "stridemap/core/error.hpp"
#include "stridemap/sensors/urg04lx.hpp"

namespace stridemap {

double RangeSigmaModel::urg_spec_range_error_m(double range_m) { return UrgModel::spec_range_error_m(range_m); }

void RangeSigmaModel::validate(const char* owner) const {
  if (!(std::isfinite(sigma_per_range_error) && sigma_per_range_error > 0.0)) {
    throw InputError(std::string(owner) + ": sigma.sigma_per_range_error is " +
                     std::to_string(sigma_per_range_error) + "; it must be finite and positive");
  }
}

}  // namespace stridemap
