#include "stridemap/core/map_layer.hpp"

#include <array>
#include <cmath>

#include "stridemap/core/error.hpp"

namespace stridemap {
namespace {

const std::array<LayerSpec, 7>& declarations() {
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  // Widest first, so that a file laying them out in this order keeps every
  // layer aligned to its element size. The texts are the map file's.
  static const std::array<LayerSpec, 7> specs{{
      {"elevation", LayerType::f32, kNaN, "m", "eq. (10): elevation of the cell; NaN when unknown", true},
      {"certainty", LayerType::f32, 0.0, "", "eq. (9): certainty of the cell; 0 when unknown or filled", true},
      {"mean_elevation", LayerType::f32, kNaN, "m", "mean of the readings eq. (9) accepted; NaN when unknown",
       false},
      {"pending_elevation", LayerType::f32, kNaN, "m",
       "gated rule: highest contradicting reading since the last plausible one; NaN when none", false},
      {"mean_count", LayerType::u16, 0.0, "", "readings in mean_elevation (saturates at 65535)", false},
      {"state", LayerType::u8, 0.0, "", "0 unknown, 1 measured, 2 filled (eq. 11)", true},
      {"contradictions", LayerType::u8, 0.0, "", "gated rule: contradicting readings since the last plausible one",
       false},
  }};
  return specs;
}

bool valid_name(const std::string& name) {
  if (name.empty() || name.size() > 64) return false;
  for (const char c : name) {
    if (!((c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_')) return false;
  }
  return true;
}

}  // namespace

const char* layer_type_name(LayerType type) {
  switch (type) {
    case LayerType::f32: return "f32";
    case LayerType::u16: return "u16";
    case LayerType::u8: break;
  }
  return "u8";
}

std::span<const LayerSpec> builtin_layers() { return declarations(); }

void validate_layer_spec(const LayerSpec& spec) {
  if (!valid_name(spec.name)) {
    throw InputError("map layer '" + spec.name +
                     "': a layer name is 1 to 64 lower-case letters, digits or '_'");
  }
  const double v = spec.reset_value;
  const auto out_of = [&](double top) { return !(v >= 0.0 && v <= top && std::floor(v) == v); };
  if ((spec.type == LayerType::u16 && out_of(65535.0)) || (spec.type == LayerType::u8 && out_of(255.0))) {
    throw InputError("map layer '" + spec.name + "': reset value " + std::to_string(v) + " does not fit type " +
                     layer_type_name(spec.type));
  }
}

}  // namespace stridemap
