// Range calibration CSV files and the cubic fit on what they hold.
#include <cmath>
#include <sstream>
#include <string>

#include "fuzz_target.hpp"
#include "stridemap/config/calibration_csv.hpp"
#include "stridemap/core/error.hpp"
#include "stridemap/sensors/range_calibration.hpp"

STRIDEMAP_FUZZ_TARGET(calibration_csv) {
  using namespace stridemap;
  std::istringstream input{std::string(fuzz::as_text(data))};
  try {
    const RangePairs pairs = read_range_pairs_csv(input, "fuzz.csv");
    fuzz::check(pairs.measured_m.size() == pairs.true_m.size() && pairs.line.size() == pairs.true_m.size(),
                "pair columns of different lengths");
    for (std::size_t i = 0; i < pairs.true_m.size(); ++i) {
      fuzz::check(std::isfinite(pairs.measured_m[i]) && pairs.measured_m[i] > 0 && std::isfinite(pairs.true_m[i]) &&
                      pairs.true_m[i] > 0,
                  "the reader let through a range that is not finite and positive");
    }
    const RangeCalibrationFit fit = fit_range_calibration(pairs.measured_m, pairs.true_m);
    (void)fit;
  } catch (const InputError&) {
  }
}
