#pragma once
// Checks that every cell of a map is in a valid state, and a fingerprint of
// the layers for comparing runs bit for bit (the soak test,
// docs/reliability.md). Neither allocates unless a problem is found.
#include <cstddef>
#include <cstdint>
#include <string>

#include "stridemap/core/grid_map.hpp"

namespace stridemap {

struct MapIntegrity {
  std::size_t unknown = 0;
  std::size_t measured = 0;
  std::size_t filled = 0;
  std::size_t invalid = 0;  ///< cells breaking a rule below
  /// The first invalid cell and what is wrong with it; empty when none.
  std::string first_problem;
  bool ok() const { return invalid == 0; }
};

/// The rules: unknown cells have NaN elevation and certainty 0; measured
/// cells a finite elevation and a certainty in (0, certainty_max]; filled
/// cells a finite elevation and certainty 0; no other state exists.
MapIntegrity check_map_integrity(const ElevationMap& map, double certainty_max);

/// FNV-1a over the window's corner cell and the elevation, certainty and
/// state of every cell in window order (so independent of where the
/// circular buffer happens to start). Equal maps give equal hashes; NaN
/// elevations are hashed by their bits.
std::uint64_t map_layers_hash(const ElevationMap& map);

}  // namespace stridemap
