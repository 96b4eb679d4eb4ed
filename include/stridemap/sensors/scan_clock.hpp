#pragma once
// Host time of a scan from the sensor's own clock. The URG stamps each scan
// with its millisecond counter at step 0; the host only knows when the last
// byte arrived, which is later by the sweep, the transmission and a delay
// that varies (USB polling, scheduling). The variable part is never
// negative, so the smallest (receive time - sensor time) over recent scans
// is the offset between the two clocks plus the fixed delay: the passive
// synchronisation of Olson (2010), with a sliding window so that drift
// between the clocks is followed. Subtracting the fixed delay (by default
// one scan period: the sensor is assumed to send a scan when the turn ends)
// gives the host time of step 0, without the jitter of the receive time.
//
// The offset falls whenever a scan arrives with less delay than any in the
// window (at the start above all, and when frames that waited in a buffer
// are read in one go: they share a receive time). Applied at once, the fall
// can put a scan at or before the previous scan's host time, which a mapper
// must refuse; so the host time is held to advance by at least half the
// sensor's own step, and the estimate catches up within a few scans.
#include <cstddef>
#include <cstdint>
#include <deque>
#include <utility>

namespace stridemap {

class ScanClock {
 public:
  /// `window` scans are kept (at least 1); `fixed_delay_s` is subtracted.
  explicit ScanClock(std::size_t window = 100, double fixed_delay_s = 0.1);

  /// Adds a scan's sensor time and receive time (both in seconds, on their
  /// own clocks) and returns the host time of its step 0. For sensor times
  /// that increase, the host times returned increase too.
  double add(double sensor_time_s, double host_receive_time_s);
  /// Host time of a sensor time, with the current offset (0 before add()).
  double host_time_of(double sensor_time_s) const;
  void reset();
  void set_fixed_delay(double fixed_delay_s) { fixed_delay_s_ = fixed_delay_s; }
  /// Current estimate of host - sensor time [s].
  double offset_s() const;

 private:
  std::size_t window_;
  double fixed_delay_s_;
  std::uint64_t count_ = 0;
  std::deque<std::pair<std::uint64_t, double>> minima_;  // (index, offset), increasing offsets
  bool have_last_ = false;
  double last_sensor_s_ = 0.0, last_host_s_ = 0.0;
};

}  // namespace stridemap
