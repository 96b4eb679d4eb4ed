#pragma once
// What has moved (beyond the paper): the URG-04LX on the cart rail, out and
// back (the scene's rail, then the same positions in reverse), maps a
// scene whose boxes come and go (BoxObject::present_from_s / _until_s: an
// object taken away, a foot passing through the scan), once with the
// visibility clean-up (core/visibility_clearing.hpp) and once without.
// Per box that leaves: the cells of its footprint still standing (above
// the truth of the time) scan by scan after it left, and how many scans the
// clean-up took to clear them; over the whole run, the cells it cleared
// whose height was right (wrongly lowered).
//
// Results are from the simulator, not from a real sensor.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "stridemap/core/progress.hpp"
#include "stridemap/core/terrain_mapper.hpp"
#include "stridemap/core/visibility_clearing.hpp"
#include "stridemap/sensors/urg04lx.hpp"
#include "stridemap/sim/scene.hpp"
#include "stridemap/sim/urg_simulator.hpp"

namespace stridemap {

struct MovedObjectsOptions {
  std::uint64_t seed = 1;
  SensorMount mount{};  ///< the paper's Messor mount
  UrgParameters urg{};
  UrgSimOptions sim{};
  UpdateOptions update{};
  double cell_size_m = 0.01;
  /// The clean-up of the "on" run (enabled is set per run).
  VisibilityOptions visibility{};
  /// A cell stands when its elevation exceeds the truth of the time by
  /// more than this [m]; a cleared cell of at most this much was right.
  double standing_above_m = 0.02;
  ProgressCallback progress{};
};

struct MovedObjectTrack {
  std::string name;
  double left_at_s = 0.0;                 ///< present_until_s
  std::size_t left_at_scan = 0;           ///< first scan without it
  std::size_t standing_when_left = 0;     ///< footprint cells standing after its last scan
  /// Standing cells after each scan from left_at_scan on.
  std::vector<std::size_t> standing;
  /// Scans after it left until at most half of standing_when_left stood,
  /// and until none stood; empty when never.
  std::optional<std::size_t> scans_until_half_cleared;
  std::optional<std::size_t> scans_until_cleared;
};

struct MovedObjectsRun {
  bool visibility = false;
  std::vector<MovedObjectTrack> objects;
  std::size_t cells_contradicted = 0;  ///< per scan, summed
  std::size_t cells_cleared = 0;
  std::size_t cells_wrongly_cleared = 0;  ///< cleared while within standing_above_m of the truth
};

struct MovedObjectsResult {
  std::size_t scans = 0;
  MovedObjectsRun off, on;
};

/// Throws InputError when the scene has no cart_rail, no box that leaves,
/// or is unusable. Deterministic for options.seed.
MovedObjectsResult run_moved_objects(const Scene& scene, const MovedObjectsOptions& options);

/// The results as a plain-text table (stdout).
std::string moved_objects_table(const MovedObjectsResult& result);
/// summary.json, table.txt and standing.png into `directory`.
void write_moved_objects_outputs(const MovedObjectsResult& result, const MovedObjectsOptions& options,
                                 const std::string& scene_path, const std::string& directory);

}  // namespace stridemap
