// Structured-light configuration files. Whatever the reader accepts must
// make a model that back-projects pixels to finite points (or says why not).
#include <cmath>
#include <string>

#include "fuzz_target.hpp"
#include "stridemap/config/structured_light_config.hpp"
#include "stridemap/core/error.hpp"
#include "stridemap/sensors/structured_light.hpp"

STRIDEMAP_FUZZ_TARGET(structured_light_config) {
  using namespace stridemap;
  StructuredLightConfig config;
  try {
    config = parse_structured_light_config(std::string(fuzz::as_text(data)), "fuzz.yaml");
  } catch (const InputError&) {
    return;
  }
  try {
    const StructuredLightModel model(config.parameters);
    const double w = config.parameters.image_width_px, h = config.parameters.image_height_px;
    for (int k = 0; k <= 4; ++k) {
      Eigen::Vector3d point;
      if (model.back_project(w * k / 4.0, h * (4 - k) / 4.0, point) == StripePointStatus::valid) {
        fuzz::check(point.allFinite(), "a valid stripe point that is not finite");
      }
    }
  } catch (const InputError& e) {
    fuzz::failure(std::string("the reader accepted parameters the model rejects: ") + e.what());
  }
}
