#include "stridemap/sensors/scip_scan.hpp"

#include <string>

#include "stridemap/core/error.hpp"

namespace stridemap::scip {

std::uint64_t TimestampUnwrapper::unwrap(std::uint32_t raw_ms) {
  if (raw_ms >= kPeriodMs) {
    throw InputError("SCIP timestamp " + std::to_string(raw_ms) + " ms does not fit 24 bits");
  }
  if (!started_) {
    started_ = true;
    count_ms_ = raw_ms;
  } else {
    count_ms_ += (raw_ms - previous_raw_) & (kPeriodMs - 1u);
  }
  previous_raw_ = raw_ms;
  return count_ms_;
}

void to_urg_raw_scan(const Event& event, double time_s, UrgRawScan& out) {
  if (event.kind != EventKind::distance || !is_distance_command(event.reply.echo.type)) {
    throw InputError("SCIP: event is not a distance reply (echo '" + event.reply.echo.text + "')");
  }
  out.time_s = time_s;
  out.first_step = event.reply.echo.start_step;
  out.cluster = event.reply.echo.cluster < 1 ? 1 : event.reply.echo.cluster;
  out.values_mm.assign(event.distance.values.begin(), event.distance.values.end());
}

}  // namespace stridemap::scip
