// PNG files as io reads them (rendered maps; camera frames later). A decoded
// image must hold exactly width x height RGB pixels.
#include <string>

#include "fuzz_target.hpp"
#include "stridemap/core/error.hpp"
#include "stridemap/render/png_image.hpp"

STRIDEMAP_FUZZ_TARGET(png_image) {
  using namespace stridemap;
  try {
    const io::RgbImage image = io::read_png(data, "fuzz.png");
    fuzz::check(image.width > 0 && image.height > 0 &&
                    image.rgb.size() == 3 * static_cast<std::size_t>(image.width) * image.height,
                "a decoded image whose buffer does not match its size");
  } catch (const InputError&) {
  }
}
