#include "stridemap/sim/receiver_gain.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "stridemap/core/error.hpp"
#include "stridemap/sim/scene_problem.hpp"

namespace stridemap {
namespace {

void check_receiver_option(const char* field, std::optional<std::string> problem) {
  if (problem) throw InputError(std::string("URG simulator options: receiver.") + field + ": " + *problem);
}

}  // namespace

void ReceiverGainOptions::validate() const {
  check_receiver_option("delay_m_per_decade", scene_rules::non_negative(delay_m_per_decade));
  check_receiver_option("advance_m_per_decade", scene_rules::non_negative(advance_m_per_decade));
  check_receiver_option("max_shift_m", scene_rules::non_negative(max_shift_m));
  check_receiver_option("headroom_decades", scene_rules::non_negative(headroom_decades));
}

ReceiverGain::ReceiverGain(const ReceiverGainOptions& options, double floor_amplitude)
    : options_(options), floor_amplitude_(floor_amplitude) {
  options_.validate();
  if (!(floor_amplitude > 0.0) || !std::isfinite(floor_amplitude)) {
    throw InputError("receiver gain: the floor amplitude must be positive and finite, got " +
                     scene_rules::format_number(floor_amplitude));
  }
}

double ReceiverGain::shift_for(double amplitude, double state_amplitude) const {
  if (!options_.enabled) return 0.0;
  const double level = std::max(amplitude, floor_amplitude_);
  const double state = std::max(state_amplitude, floor_amplitude_);
  const double decades = std::log10(level / state);
  const double beyond_headroom = std::max(0.0, std::abs(decades) - options_.headroom_decades);
  const double shift =
      decades < 0.0 ? options_.delay_m_per_decade * beyond_headroom : -options_.advance_m_per_decade * beyond_headroom;
  return std::clamp(shift, -options_.max_shift_m, options_.max_shift_m);
}

double ReceiverGain::shift_m(double amplitude) {
  const double shift = state_ ? shift_for(amplitude, *state_) : 0.0;
  state_ = amplitude;
  return shift;
}

}  // namespace stridemap
