#pragma once
// What the URG emulator measures: one scan's raw values (millimetres, error
// codes below 20 kept, one value per step, steps AMIN..AMAX) for the scan
// that starts at a given time. Either simulated (the simulator's physics
// from a motion's true pose) or replayed from recorded scans.
#include <cstdint>
#include <memory>
#include <vector>

#include "stridemap/core/pose.hpp"
#include "stridemap/sensors/urg04lx.hpp"
#include "stridemap/sim/motion_source.hpp"
#include "stridemap/sim/urg_simulator.hpp"

namespace stridemap {

class UrgScanSource {
 public:
  virtual ~UrgScanSource() = default;
  /// Fills `values_mm` with one value per step first_step..last_step of the
  /// sensor's parameters, for scan `index` (counted since the sensor started
  /// turning) that starts at `time_s` seconds of simulation time.
  virtual void scan(std::uint64_t index, double time_s, std::vector<std::uint32_t>& values_mm) = 0;
};

/// Noise seed of scan `index` of a run seeded with `seed` (splitmix64 of
/// both): each scan's noise depends on the run's seed and the scan's own
/// number only, not on which scans a host happened to ask for.
std::uint64_t scan_noise_seed(std::uint64_t seed, std::uint64_t index);

/// UrgSimulator driven by a motion: scan `index` is simulated from the true
/// pose motion.pose_at(time_s), with noise seeded by scan_noise_seed(seed, index).
class SimulatedScanSource final : public UrgScanSource {
 public:
  /// Keeps a reference to `motion`, which must outlive the source.
  SimulatedScanSource(std::unique_ptr<UrgSimulator> simulator, const MotionSource& motion, const SensorMount& mount,
                      std::uint64_t seed);
  void scan(std::uint64_t index, double time_s, std::vector<std::uint32_t>& values_mm) override;
  const UrgSimulator& simulator() const { return *simulator_; }

 private:
  std::unique_ptr<UrgSimulator> simulator_;
  const MotionSource& motion_;
  SensorMount mount_;
  std::uint64_t seed_;
  UrgRawScan raw_;
};

/// Recorded scans played back in order, from the first again after the last.
class RecordedScanSource final : public UrgScanSource {
 public:
  /// `scans` hold values from `first_step` on, `cluster` steps per value (a
  /// clustered value is repeated over its steps). Steps of the sensor that a
  /// recording does not cover get code 19 ("non-measurable step"). Throws
  /// InputError for no scans, a cluster below 1 or a negative first step.
  RecordedScanSource(std::vector<std::vector<std::uint32_t>> scans, int first_step, int cluster,
                     const UrgParameters& parameters);
  void scan(std::uint64_t index, double time_s, std::vector<std::uint32_t>& values_mm) override;
  std::size_t size() const { return scans_.size(); }

 private:
  std::vector<std::vector<std::uint32_t>> scans_;
  int first_step_;
  int cluster_;
  UrgParameters parameters_;
};

}  // namespace stridemap
