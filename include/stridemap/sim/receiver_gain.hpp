#pragma once
// Range-intensity coupling through the receiver's automatic gain control
// (AGC): the physics behind the paper's mixed measurements "behind the
// farther object, or in front of the closer object" (section 5.3), modelled
// as research/algorithms.md 4.4 describes the chain: photodiode, amplifier,
// limiter, AGC, phase meter. The phase delay of the amplifier-limiter chain
// depends on the signal level at its input, and the level is the echo
// amplitude times the gain the AGC has set. A receiver calibrated in steady
// state (the AGC settled on the echo being measured) reads true; but an AGC
// that sets the gain for beam i from the echo of beam i-1 (it measures the
// level during one step and applies it on the next) sees a level off its
// target on the first beam after an amplitude step:
//
//   x = log10(A_i / A_state)   [decades; A_state = echo amplitude of the
//                               previous beam, floored at the dropout
//                               threshold, the end of the AGC's range]
//   e = max(0, |x| - headroom_decades)  (the limiter's headroom)
//   shift = +delay_m_per_decade * e     for x < 0 (weaker: reads farther)
//   shift = -advance_m_per_decade * e   for x > 0 (stronger: reads nearer)
//   |shift| <= max_shift_m              (the limiter bounds the phase error)
//
// The headroom: the AGC holds the limiter's input above the level where
// limiting begins, and while the input stays in limiting the phase delay does
// not depend on it. An echo a little weaker or stronger than the state (a
// textured surface, the floor weakening towards grazing incidence) is still
// limited and reads true; only a step larger than the headroom (a depth jump,
// a change of material) drives the limiter out of its range.
//
// b(A) is a smooth monotone function of log A (algorithms.md 4.4) whose
// reference is the gain state, not an absolute amplitude: inside one surface
// the amplitude changes little from beam to beam and the shift stays at a
// millimetre or less, while at a depth or reflectance step the first beam
// on the weaker surface reads behind it and the first beam on the stronger
// one in front of it. The advance is the smaller: an overdriven limiter
// saturates, an underdriven one falls out of limiting and its delay grows
// (the real logs show readings behind a jump about seven times as often as
// in front, docs/mixed_pixels.md). Slopes are calibrated, not published.
#include <optional>

namespace stridemap {

struct ReceiverGainOptions {
  /// true (the default): the coupling acts on the echoes of every beam
  /// model that takes it (the footprint model; not the ideal single ray,
  /// BeamModel::takes_receiver_coupling). false: the readings of a receiver
  /// that is always settled, the simpler model.
  bool enabled = true;
  /// Range shift per decade beyond the headroom by which an echo is weaker
  /// than the gain state [m]; the echo reads farther. 0.4 with the 0.15
  /// decade headroom: at depth jumps of terrain scans the middle beam then
  /// reads more than 30 mm behind the far surface at about the rate the
  /// real logs show behind jumps in scan order (0.20 % of jumps, real 0.29
  /// %; docs/mixed_pixels.md, "Range-intensity coupling").
  double delay_m_per_decade = 0.4;
  /// Range shift per decade beyond the headroom by which an echo is
  /// stronger than the gain state [m]; the echo reads nearer. An eighth of
  /// the delay: the real logs show readings in front of a jump about an
  /// eighth as often as behind it (fast attack, slow release, as AGCs are
  /// built).
  double advance_m_per_decade = 0.05;
  /// The limiter's headroom [decades]: an echo within this of the gain
  /// state keeps the limiter limiting and reads true. 0.15 (a factor of
  /// 1.4): the scatter a textured surface's beam-to-beam changes would get
  /// from the lag falls from 7.1 to 0.7 mm rms, below the sensor's own
  /// noise, while the steps at terrain edges (0.3 to 1 decade) still read
  /// off their surface (docs/mixed_pixels.md, "The limiter's headroom"). 0
  /// gives the plain lag.
  double headroom_decades = 0.15;
  /// Bound on |shift| [m]: the limiter bounds the phase error. 0.15 m lets
  /// through the 31-137 mm that most readings behind a jump in the real
  /// logs show (24 of 28; whole-period wraps left out).
  double max_shift_m = 0.15;

  /// Throws InputError "URG simulator options: receiver.<field>: <problem>".
  void validate() const;
};

/// The AGC's state across one scan. Call begin_scan() before the first beam
/// and shift_m() or no_echo() once per beam, in beam order.
class ReceiverGain {
 public:
  /// floor_amplitude: the weakest echo the AGC can settle on (the dropout
  /// threshold); must be positive.
  ReceiverGain(const ReceiverGainOptions& options, double floor_amplitude);

  /// The mirror passes the sensor's back between scans and no light
  /// returns: the first beam of a scan has no state to lag behind.
  void begin_scan() { state_.reset(); }
  /// Range shift of an echo of this amplitude [m] (0 when disabled, on the
  /// first echo of a scan, and for an amplitude equal to the state); then
  /// the AGC settles on it.
  double shift_m(double amplitude);
  /// A beam with no echo: the gain is held.
  void no_echo() {}

  /// The shift an echo of `amplitude` gets under a gain state set by
  /// `state_amplitude`, without changing the state [m].
  double shift_for(double amplitude, double state_amplitude) const;

 private:
  ReceiverGainOptions options_;
  double floor_amplitude_ = 0.0;
  std::optional<double> state_;
};

}  // namespace stridemap
