#pragma once
// A map layer is a declaration: its name, element type, the value a cell
// holds before any measurement, its unit and meaning. ElevationMap keeps one
// array per declared layer; the seven it needs itself are declared here
// like any other, and a user adds more (GridOptions::extra_layers or
// ElevationMap::add_layer) without touching the library. Code that updates
// a layer asks once for a typed LayerId and then indexes the layer's array
// by slot: no name look-up on the per-point path.
#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>
#include <string>
#include <type_traits>

namespace stridemap {

/// Element types a layer can hold; enough for heights, counters and flags.
enum class LayerType : std::uint8_t { f32, u16, u8 };

constexpr std::size_t layer_type_bytes(LayerType type) {
  return type == LayerType::f32 ? 4 : type == LayerType::u16 ? 2 : 1;
}
/// "f32", "u16", "u8": for messages and `map-info`.
const char* layer_type_name(LayerType type);

template <typename T>
constexpr LayerType layer_type_of() {
  static_assert(std::is_same_v<T, float> || std::is_same_v<T, std::uint16_t> || std::is_same_v<T, std::uint8_t>,
                "a layer holds float, std::uint16_t or std::uint8_t");
  if constexpr (std::is_same_v<T, float>) return LayerType::f32;
  if constexpr (std::is_same_v<T, std::uint16_t>) return LayerType::u16;
  return LayerType::u8;
}

struct LayerSpec {
  /// Lower-case letters, digits and '_', unique within a map: how outputs
  /// (`export --layers`, the map file) select it.
  std::string name;
  LayerType type = LayerType::f32;
  /// What a cell holds when the window first covers it or clear() runs
  /// (NaN allowed for f32; whole numbers within range for the integers).
  double reset_value = 0.0;
  std::string unit;         ///< "m"; empty for counts and flags
  std::string description;  ///< one line, for the map file and `map-info`
  /// In export_map()'s default selection (the planner's view); the update
  /// rule's bookkeeping is not.
  bool exported = true;
};

/// A typed handle to one layer of a map: its place in the map's registry.
/// Valid for the map it came from and for copies of it.
template <typename T>
struct LayerId {
  std::size_t index = 0;
};

/// The layers every ElevationMap has, at these places in its registry.
namespace layers {
inline constexpr LayerId<float> elevation{0};
inline constexpr LayerId<float> certainty{1};
inline constexpr LayerId<float> mean_elevation{2};
inline constexpr LayerId<float> pending_elevation{3};
inline constexpr LayerId<std::uint16_t> mean_count{4};
inline constexpr LayerId<std::uint8_t> state{5};
inline constexpr LayerId<std::uint8_t> contradictions{6};
}  // namespace layers

/// Declarations of the layers above, in registry order (which is also the
/// map file's order: widest elements first).
std::span<const LayerSpec> builtin_layers();

/// Throws InputError when the declaration is unusable: a bad or empty name,
/// a reset value the type cannot hold.
void validate_layer_spec(const LayerSpec& spec);

}  // namespace stridemap
