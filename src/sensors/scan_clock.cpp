#include "stridemap/sensors/scan_clock.hpp"

#include <algorithm>

namespace stridemap {

ScanClock::ScanClock(std::size_t window, double fixed_delay_s)
    : window_(std::max<std::size_t>(window, 1)), fixed_delay_s_(fixed_delay_s) {}

double ScanClock::add(double sensor_time_s, double host_receive_time_s) {
  const double offset = host_receive_time_s - sensor_time_s;
  // Monotone deque: the front is the minimum of the last window_ offsets.
  while (!minima_.empty() && minima_.back().second >= offset) minima_.pop_back();
  minima_.emplace_back(count_, offset);
  while (minima_.front().first + window_ <= count_) minima_.pop_front();
  ++count_;
  double host_s = host_time_of(sensor_time_s);
  if (have_last_ && sensor_time_s > last_sensor_s_) {
    host_s = std::max(host_s, last_host_s_ + 0.5 * (sensor_time_s - last_sensor_s_));
  }
  have_last_ = true;
  last_sensor_s_ = sensor_time_s;
  last_host_s_ = host_s;
  return host_s;
}

double ScanClock::offset_s() const { return minima_.empty() ? 0.0 : minima_.front().second - fixed_delay_s_; }

double ScanClock::host_time_of(double sensor_time_s) const { return sensor_time_s + offset_s(); }

void ScanClock::reset() {
  minima_.clear();
  count_ = 0;
  have_last_ = false;
}

}  // namespace stridemap
