#pragma once
// From a decoded SCIP distance reply to the sensor model's raw scan, and the
// sensor's 24-bit millisecond clock turned into a count that does not wrap.
#include <cstdint>

#include "stridemap/sensors/scip_decoder.hpp"
#include "stridemap/sensors/urg04lx.hpp"

namespace stridemap::scip {

/// Unwraps the sensor's 24-bit millisecond timestamp (it wraps every 2^24 ms,
/// about 4 h 40 min) into a 64-bit count that never decreases: each new
/// timestamp advances the count by its distance from the previous one modulo
/// 2^24. So it tolerates any number of wraps, provided timestamps arrive less
/// than 2^24 ms apart. After RS (which resets the sensor's timer) call reset().
class TimestampUnwrapper {
 public:
  static constexpr std::uint32_t kPeriodMs = std::uint32_t{1} << 24;

  /// Unwrapped count for `raw_ms`; the first call returns raw_ms itself.
  /// Throws InputError if raw_ms does not fit 24 bits.
  std::uint64_t unwrap(std::uint32_t raw_ms);
  /// Forget the history: the next timestamp starts a new count.
  void reset() { started_ = false; }
  /// Last value returned by unwrap() (0 before the first call).
  std::uint64_t last_ms() const { return count_ms_; }

 private:
  bool started_ = false;
  std::uint32_t previous_raw_ = 0;
  std::uint64_t count_ms_ = 0;
};

/// Copies a distance event into `out` (storage reused): first step and
/// cluster (00 counts as 1) from the echo, values as sent (error codes kept),
/// and `time_s` (the caller's choice: host time, or unwrapped sensor time /
/// 1000). Throws InputError if the event is not a distance reply.
void to_urg_raw_scan(const Event& event, double time_s, UrgRawScan& out);

}  // namespace stridemap::scip
