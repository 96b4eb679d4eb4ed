#include "stridemap/core/map_integrity.hpp"

#include <cmath>
#include <cstring>

namespace stridemap {
namespace {

constexpr std::uint64_t kFnvOffset = 14695981039346656037ULL;
constexpr std::uint64_t kFnvPrime = 1099511628211ULL;

template <typename T>
void hash_bytes(std::uint64_t& hash, const T& value) {
  unsigned char bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));
  for (unsigned char b : bytes) hash = (hash ^ b) * kFnvPrime;
}

// Empty when the cell is valid.
std::string problem_of(float elevation, float certainty, std::uint8_t state, float certainty_max) {
  const auto values = [&] {
    return "elevation " + std::to_string(elevation) + ", certainty " + std::to_string(certainty);
  };
  switch (static_cast<CellState>(state)) {
    case CellState::unknown:
      if (std::isnan(elevation) && certainty == 0.0f) return {};
      return "unknown but " + values();
    case CellState::measured:
      if (std::isfinite(elevation) && certainty > 0.0f && certainty <= certainty_max) return {};
      return "measured but " + values();
    case CellState::filled:
      if (std::isfinite(elevation) && certainty == 0.0f) return {};
      return "filled but " + values();
  }
  return "state " + std::to_string(state) + " does not exist";
}

}  // namespace

MapIntegrity check_map_integrity(const ElevationMap& map, double certainty_max) {
  MapIntegrity result;
  const auto ceiling = static_cast<float>(certainty_max);
  const int n = map.cells_per_side();
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      const CellIndex cell = map.cell_at_local(i, j);
      const std::size_t s = map.slot(cell);
      const float elevation = map.elevation_data()[s];
      const float certainty = map.certainty_data()[s];
      const std::uint8_t state = map.state_data()[s];
      const bool valid_state = state <= static_cast<std::uint8_t>(CellState::filled);
      // The common case without building a message.
      const bool valid =
          valid_state && (state == static_cast<std::uint8_t>(CellState::unknown)
                              ? std::isnan(elevation) && certainty == 0.0f
                              : std::isfinite(elevation) &&
                                    (state == static_cast<std::uint8_t>(CellState::measured)
                                         ? certainty > 0.0f && certainty <= ceiling
                                         : certainty == 0.0f));
      if (valid) {
        ++(state == 0 ? result.unknown : state == 1 ? result.measured : result.filled);
        continue;
      }
      if (result.invalid++ == 0) {
        result.first_problem = "cell (" + std::to_string(cell.x) + ", " + std::to_string(cell.y) +
                               "): " + problem_of(elevation, certainty, state, ceiling);
      }
    }
  }
  return result;
}

std::uint64_t map_layers_hash(const ElevationMap& map) {
  std::uint64_t hash = kFnvOffset;
  hash_bytes(hash, map.min_cell().x);
  hash_bytes(hash, map.min_cell().y);
  const int n = map.cells_per_side();
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      const std::size_t s = map.slot(map.cell_at_local(i, j));
      hash_bytes(hash, map.elevation_data()[s]);
      hash_bytes(hash, map.certainty_data()[s]);
      hash_bytes(hash, map.state_data()[s]);
    }
  }
  return hash;
}

}  // namespace stridemap
