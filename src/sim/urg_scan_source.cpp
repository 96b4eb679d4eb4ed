#include "stridemap/sim/urg_scan_source.hpp"

#include "stridemap/core/error.hpp"

namespace stridemap {

std::uint64_t scan_noise_seed(std::uint64_t seed, std::uint64_t index) {
  std::uint64_t z = seed + 0x9E3779B97F4A7C15ull * (index + 1);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

SimulatedScanSource::SimulatedScanSource(std::unique_ptr<UrgSimulator> simulator, const MotionSource& motion,
                                         const SensorMount& mount, std::uint64_t seed)
    : simulator_(std::move(simulator)), motion_(motion), mount_(mount), seed_(seed) {
  if (!simulator_) throw InputError("simulated scan source: no simulator");
}

void SimulatedScanSource::scan(std::uint64_t index, double time_s, std::vector<std::uint32_t>& values_mm) {
  simulator_->reset(scan_noise_seed(seed_, index));
  simulator_->scan(motion_.pose_at(time_s), mount_, time_s, raw_);
  values_mm.assign(raw_.values_mm.begin(), raw_.values_mm.end());
}

RecordedScanSource::RecordedScanSource(std::vector<std::vector<std::uint32_t>> scans, int first_step, int cluster,
                                       const UrgParameters& parameters)
    : scans_(std::move(scans)), first_step_(first_step), cluster_(cluster), parameters_(parameters) {
  if (scans_.empty()) throw InputError("recorded scan source: the recording holds no scans");
  if (cluster_ < 1) throw InputError("recorded scan source: cluster must be >= 1, got " + std::to_string(cluster_));
  if (first_step_ < 0) {
    throw InputError("recorded scan source: first step must be >= 0, got " + std::to_string(first_step_));
  }
  parameters_.validate();
}

void RecordedScanSource::scan(std::uint64_t index, double, std::vector<std::uint32_t>& values_mm) {
  constexpr std::uint32_t kDeadZoneValue = 19;
  const std::vector<std::uint32_t>& recorded = scans_[index % scans_.size()];
  values_mm.resize(static_cast<std::size_t>(parameters_.beam_count()));
  for (int step = parameters_.first_step; step <= parameters_.last_step; ++step) {
    const int offset = step - first_step_;
    const std::size_t k = offset < 0 ? recorded.size() : static_cast<std::size_t>(offset / cluster_);
    values_mm[static_cast<std::size_t>(step - parameters_.first_step)] =
        k < recorded.size() ? recorded[k] : kDeadZoneValue;
  }
}

}  // namespace stridemap
