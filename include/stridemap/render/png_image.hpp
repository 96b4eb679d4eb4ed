#pragma once
// 8-bit RGB images and their PNG files (libpng). Used for the rendered
// elevation and certainty maps; read_png lets tests and tools inspect them.
#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

namespace stridemap::io {

struct RgbImage {
  int width = 0;
  int height = 0;
  // Row-major, top row first, 3 bytes (R, G, B) per pixel: size 3 * width * height.
  std::vector<std::uint8_t> rgb;

  RgbImage() = default;
  // A width x height image filled with one colour.
  RgbImage(int image_width, int image_height, std::uint8_t red = 0, std::uint8_t green = 0,
           std::uint8_t blue = 0);

  // Byte offset of pixel (x, y) (x to the right, y down) in `rgb`.
  std::size_t offset(int x, int y) const { return 3 * (static_cast<std::size_t>(y) * width + x); }
};

// Largest width or height accepted by write_png and read_png (libpng's own
// default limit); also at most 2^28 pixels in total, so a corrupted header
// cannot make read_png allocate gigabytes.
inline constexpr int kMaxPngSide = 1000000;
inline constexpr long long kMaxPngPixels = 1LL << 28;

// Writes an 8-bit RGB PNG. The file appears at `path` only when complete: it
// is written to a temporary file in the same folder and renamed at the end.
// Throws InputError naming the path and the reason: bad dimensions or buffer
// size, missing or read-only folder, write failure (e.g. disk full).
void write_png(const std::string& path, const RgbImage& image);

// Reads any 8- or 16-bit PNG (gray, gray+alpha, RGB, RGBA, palette,
// interlaced or not) and converts it to 8-bit RGB; alpha is dropped, not
// composited. Throws InputError naming the path and the reason: cannot open,
// not a PNG, truncated or corrupted data, dimensions over the limits above.
RgbImage read_png(const std::string& path);

// What the file held before read_png converted it to 8-bit RGB, for tools
// that need colour (the stripe detector thresholds the red excess).
struct PngSourceFormat {
  bool has_colour = false;  // RGB(A) or palette; false for grey(+alpha)
  int bit_depth = 8;        // per channel (or per palette index) in the file
  std::string colour_type;  // "grey", "grey+alpha", "RGB", "RGBA" or "palette"
};

// As above, and reports the file's own format in `source`.
RgbImage read_png(const std::string& path, PngSourceFormat& source);

// What a reader knows it wants, checked from the PNG header before a pixel
// buffer exists: a valid 16000 x 16000 image that a 640 x 480 camera
// configuration would refuse must not be decoded (780 MB) first.
struct PngReadOptions {
  // At most this many pixels (width x height), on top of the limits above.
  long long max_pixels = kMaxPngPixels;
  // Called with the header's size and the file's format before decoding;
  // throws InputError to refuse the file (e.g. not the expected size).
  std::function<void(int width, int height, const PngSourceFormat& format)> check_header;
};

// As above, with the header checked against `options` first.
RgbImage read_png(const std::string& path, PngSourceFormat& source, const PngReadOptions& options);

// Same, from the bytes of a PNG file in memory; source_name stands for the
// file in messages.
RgbImage read_png(std::span<const std::uint8_t> bytes, const std::string& source_name);
RgbImage read_png(std::span<const std::uint8_t> bytes, const std::string& source_name, PngSourceFormat& source);
RgbImage read_png(std::span<const std::uint8_t> bytes, const std::string& source_name, PngSourceFormat& source,
                  const PngReadOptions& options);

}  // namespace stridemap::io
