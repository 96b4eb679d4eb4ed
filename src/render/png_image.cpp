#include "stridemap/render/png_image.hpp"

#include <png.h>
#include <sys/stat.h>

#include <algorithm>
#include <cerrno>
#include <csetjmp>
#include <cstdio>
#include <cstring>
#include <system_error>

#include "stridemap/core/error.hpp"
#include "stridemap/io/detail/atomic_output_file.hpp"
#include "stridemap/io/detail/errno_text.hpp"

namespace stridemap::io {
namespace {

// libpng reports errors through a callback that must not return. Throwing a
// C++ exception through libpng's C frames is not safe, so the callbacks
// longjmp back to the setjmp in encode/decode_* below; those functions hold
// only trivially destructible locals, and every resource lives in a guard
// owned by their caller, so nothing leaks and no destructor is skipped.
struct PngContext {
  std::FILE* file = nullptr;
  // Reading from memory instead of a file: the bytes and the read position.
  const std::uint8_t* bytes = nullptr;
  std::size_t size = 0;
  std::size_t position = 0;
  // Bytes of the whole input when known (a regular file or memory), else 0.
  std::size_t input_bytes = 0;
  char message[256] = {};
  int saved_errno = 0;
  bool truncated = false;
};

void on_png_error(png_structp png, png_const_charp message) {
  auto* context = static_cast<PngContext*>(png_get_error_ptr(png));
  std::snprintf(context->message, sizeof context->message, "%s", message);
  png_longjmp(png, 1);
}

// Warnings (an odd colour profile, an unknown chunk) leave the image usable.
void on_png_warning(png_structp, png_const_charp) {}

void write_to_file(png_structp png, png_bytep data, png_size_t length) {
  auto* context = static_cast<PngContext*>(png_get_io_ptr(png));
  if (std::fwrite(data, 1, length, context->file) != length) {
    context->saved_errno = errno;
    png_error(png, "write failed");
  }
}

void flush_file(png_structp png) {
  auto* context = static_cast<PngContext*>(png_get_io_ptr(png));
  if (std::fflush(context->file) != 0) {
    context->saved_errno = errno;
    png_error(png, "write failed");
  }
}

void read_from_file(png_structp png, png_bytep data, png_size_t length) {
  auto* context = static_cast<PngContext*>(png_get_io_ptr(png));
  if (std::fread(data, 1, length, context->file) != length) {
    if (std::ferror(context->file) != 0) {
      context->saved_errno = errno;
      png_error(png, "read failed");
    }
    context->truncated = true;
    png_error(png, "unexpected end of file");
  }
}

void read_from_memory(png_structp png, png_bytep data, png_size_t length) {
  auto* context = static_cast<PngContext*>(png_get_io_ptr(png));
  if (context->size - context->position < length) {
    context->truncated = true;
    png_error(png, "unexpected end of data");
  }
  std::memcpy(data, context->bytes + context->position, length);
  context->position += length;
}

struct WriteGuard {
  png_structp png = nullptr;
  png_infop info = nullptr;
  ~WriteGuard() { png_destroy_write_struct(&png, &info); }
};

struct ReadGuard {
  png_structp png = nullptr;
  png_infop info = nullptr;
  ~ReadGuard() { png_destroy_read_struct(&png, &info, nullptr); }
};

struct FileGuard {
  std::FILE* file = nullptr;
  ~FileGuard() {
    if (file != nullptr) std::fclose(file);
  }
};

bool encode(png_structp png, png_infop info, const RgbImage& image) {
  if (setjmp(png_jmpbuf(png))) return false;
  png_set_IHDR(png, info, static_cast<png_uint_32>(image.width), static_cast<png_uint_32>(image.height), 8,
               PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_write_info(png, info);
  for (int y = 0; y < image.height; ++y) png_write_row(png, image.rgb.data() + image.offset(0, y));
  png_write_end(png, nullptr);
  return true;
}

// Reads the header and sets up the conversion of every PNG flavour to 8-bit RGB.
bool decode_header(png_structp png, png_infop info, png_uint_32* width, png_uint_32* height, png_byte* colour_type,
                   png_byte* bit_depth) {
  if (setjmp(png_jmpbuf(png))) return false;
  png_read_info(png, info);
  *colour_type = png_get_color_type(png, info);
  *bit_depth = png_get_bit_depth(png, info);
  png_set_expand(png);  // palette -> RGB, gray below 8 bits -> 8 bits, tRNS -> alpha
  png_set_strip_16(png);
  png_set_strip_alpha(png);
  png_set_gray_to_rgb(png);
  png_set_interlace_handling(png);
  png_read_update_info(png, info);
  *width = png_get_image_width(png, info);
  *height = png_get_image_height(png, info);
  if (png_get_rowbytes(png, info) != 3 * static_cast<png_size_t>(*width)) {
    png_error(png, "conversion to 8-bit RGB failed");
  }
  return true;
}

// Non-interlaced images row by row into a buffer that grows with the data,
// so that a few bytes claiming a huge image cannot make us allocate and
// clear hundreds of megabytes before the data runs out.
bool decode_rows(png_structp png, std::vector<std::uint8_t>& rgb, png_uint_32 height, std::size_t row_bytes) {
  if (setjmp(png_jmpbuf(png))) return false;
  for (png_uint_32 y = 0; y < height; ++y) {
    rgb.resize(rgb.size() + row_bytes);
    png_read_row(png, rgb.data() + rgb.size() - row_bytes, nullptr);
  }
  png_read_end(png, nullptr);
  return true;
}

bool decode_pixels(png_structp png, png_bytepp rows) {
  if (setjmp(png_jmpbuf(png))) return false;
  png_read_image(png, rows);
  // Reading up to IEND verifies that the file is complete and its CRCs hold.
  png_read_end(png, nullptr);
  return true;
}


std::string decode_failure(const std::string& path, const PngContext& context) {
  std::string reason;
  if (context.saved_errno != 0) {
    reason = "read failed (" + detail::errno_text(context.saved_errno) + ")";
  } else if (context.truncated) {
    reason = "the file is truncated (it ends before the image is complete)";
  } else {
    reason = std::string("corrupted or unsupported PNG data (libpng: ") + context.message + ")";
  }
  return "cannot read PNG '" + path + "': " + reason;
}

// Everything after the 8 signature bytes, from the context's file or memory.
RgbImage decode_png(PngContext& context, png_rw_ptr read, const std::string& path, PngSourceFormat& source,
                    const PngReadOptions& options) {
  ReadGuard guard;
  guard.png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &context, on_png_error, on_png_warning);
  if (guard.png != nullptr) guard.info = png_create_info_struct(guard.png);
  if (guard.png == nullptr || guard.info == nullptr) {
    throw InputError("cannot read PNG '" + path + "': libpng could not be initialised");
  }
  png_set_read_fn(guard.png, &context, read);
  png_set_sig_bytes(guard.png, 8);
  png_set_user_limits(guard.png, kMaxPngSide, kMaxPngSide);

  png_uint_32 width = 0;
  png_uint_32 height = 0;
  png_byte colour_type = 0;
  png_byte bit_depth = 0;
  if (!decode_header(guard.png, guard.info, &width, &height, &colour_type, &bit_depth)) {
    throw InputError(decode_failure(path, context));
  }
  source.bit_depth = bit_depth;
  source.has_colour = (colour_type & PNG_COLOR_MASK_COLOR) != 0;
  switch (colour_type) {
    case PNG_COLOR_TYPE_GRAY: source.colour_type = "grey"; break;
    case PNG_COLOR_TYPE_GRAY_ALPHA: source.colour_type = "grey+alpha"; break;
    case PNG_COLOR_TYPE_PALETTE: source.colour_type = "palette"; break;
    case PNG_COLOR_TYPE_RGB_ALPHA: source.colour_type = "RGBA"; break;
    default: source.colour_type = "RGB"; break;
  }
  const long long max_pixels = std::min(options.max_pixels, kMaxPngPixels);
  if (static_cast<long long>(width) * height > max_pixels) {
    throw InputError("cannot read PNG '" + path + "': image dimensions " + std::to_string(width) + " x " +
                     std::to_string(height) + " exceed the limit of " + std::to_string(max_pixels) + " pixels");
  }
  // Only the header has been read so far: a refusal here costs nothing.
  if (options.check_header) options.check_header(static_cast<int>(width), static_cast<int>(height), source);
  if (png_get_interlace_type(guard.png, guard.info) == PNG_INTERLACE_NONE) {
    RgbImage image;
    image.width = static_cast<int>(width);
    image.height = static_cast<int>(height);
    if (!decode_rows(guard.png, image.rgb, height, 3 * static_cast<std::size_t>(width))) {
      throw InputError(decode_failure(path, context));
    }
    return image;
  }
  // Interlaced passes revisit every row: the whole image is needed at once.
  // Deflate cannot expand data more than 1032-fold, so an input too short
  // to hold the image the header claims is refused before that allocation.
  const int channels = colour_type == PNG_COLOR_TYPE_GRAY_ALPHA ? 2
                       : colour_type == PNG_COLOR_TYPE_RGB      ? 3
                       : colour_type == PNG_COLOR_TYPE_RGB_ALPHA ? 4
                                                                 : 1;
  const double source_bytes = static_cast<double>(width) * height * channels * bit_depth / 8.0;
  constexpr double kMaxDeflateExpansion = 1032.0;
  if (context.input_bytes > 0 && source_bytes > kMaxDeflateExpansion * static_cast<double>(context.input_bytes)) {
    throw InputError("cannot read PNG '" + path + "': the file is truncated or corrupted: its interlaced " +
                     std::to_string(width) + " x " + std::to_string(height) + " image needs at least " +
                     std::to_string(static_cast<long long>(source_bytes / kMaxDeflateExpansion)) +
                     " bytes of compressed data, the whole file has " + std::to_string(context.input_bytes));
  }
  RgbImage image(static_cast<int>(width), static_cast<int>(height));
  std::vector<png_bytep> rows(height);
  for (png_uint_32 y = 0; y < height; ++y) rows[y] = image.rgb.data() + image.offset(0, static_cast<int>(y));
  if (!decode_pixels(guard.png, rows.data())) throw InputError(decode_failure(path, context));
  return image;
}

}  // namespace

RgbImage::RgbImage(int image_width, int image_height, std::uint8_t red, std::uint8_t green, std::uint8_t blue)
    : width(image_width), height(image_height) {
  if (image_width < 0 || image_height < 0) {
    throw InputError("RgbImage: negative size " + std::to_string(image_width) + " x " +
                     std::to_string(image_height));
  }
  rgb.resize(3 * static_cast<std::size_t>(image_width) * static_cast<std::size_t>(image_height));
  for (std::size_t i = 0; i < rgb.size(); i += 3) {
    rgb[i] = red;
    rgb[i + 1] = green;
    rgb[i + 2] = blue;
  }
}

void write_png(const std::string& path, const RgbImage& image) {
  const auto fail_early = [&](const std::string& reason) {
    throw InputError("cannot write PNG '" + path + "': " + reason);
  };
  const std::string size_text = std::to_string(image.width) + " x " + std::to_string(image.height);
  if (image.width <= 0 || image.height <= 0) fail_early("bad image dimensions " + size_text + " (must be positive)");
  if (image.width > kMaxPngSide || image.height > kMaxPngSide ||
      static_cast<long long>(image.width) * image.height > kMaxPngPixels) {
    fail_early("image dimensions " + size_text + " exceed the limit");
  }
  const std::size_t expected = 3 * static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height);
  if (image.rgb.size() != expected) {
    fail_early("pixel buffer holds " + std::to_string(image.rgb.size()) + " bytes, " + size_text + " RGB needs " +
               std::to_string(expected));
  }

  detail::AtomicOutputFile out(path, "PNG");
  PngContext context;
  context.file = out.stream();
  {
    WriteGuard guard;
    guard.png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &context, on_png_error, on_png_warning);
    if (guard.png == nullptr) out.fail("libpng could not be initialised");
    guard.info = png_create_info_struct(guard.png);
    if (guard.info == nullptr) out.fail("libpng could not be initialised");
    png_set_write_fn(guard.png, &context, write_to_file, flush_file);
    if (!encode(guard.png, guard.info, image)) {
      out.fail(context.saved_errno != 0 ? "write failed (" + detail::errno_text(context.saved_errno) + ")"
                                        : std::string("libpng: ") + context.message);
    }
  }
  out.commit();
}

RgbImage read_png(const std::string& path) {
  PngSourceFormat ignored;
  return read_png(path, ignored);
}

RgbImage read_png(const std::string& path, PngSourceFormat& source) { return read_png(path, source, PngReadOptions{}); }

RgbImage read_png(const std::string& path, PngSourceFormat& source, const PngReadOptions& options) {
  FileGuard file{std::fopen(path.c_str(), "rb")};
  if (file.file == nullptr) {
    const int error_number = errno;
    throw InputError("cannot read PNG '" + path + "': " +
                     (error_number == ENOENT ? std::string("the file does not exist")
                                             : "cannot open it (" + detail::errno_text(error_number) + ")"));
  }
  png_byte signature[8] = {};
  const std::size_t signature_size = std::fread(signature, 1, sizeof signature, file.file);
  if (signature_size < sizeof signature && std::ferror(file.file) != 0) {
    throw InputError("cannot read PNG '" + path + "': read failed (" + detail::errno_text(errno) + ")");
  }
  if (signature_size < sizeof signature || png_sig_cmp(signature, 0, sizeof signature) != 0) {
    throw InputError("cannot read PNG '" + path + "': not a PNG file (" +
                     (signature_size < sizeof signature
                          ? "only " + std::to_string(signature_size) + " bytes long"
                          : std::string("the first 8 bytes are not the PNG signature")) +
                     ")");
  }

  PngContext context;
  context.file = file.file;
  struct stat status {};
  if (::fstat(::fileno(file.file), &status) == 0 && S_ISREG(status.st_mode)) {
    context.input_bytes = static_cast<std::size_t>(status.st_size);
  }
  return decode_png(context, read_from_file, path, source, options);
}

RgbImage read_png(std::span<const std::uint8_t> bytes, const std::string& source_name) {
  PngSourceFormat ignored;
  return read_png(bytes, source_name, ignored);
}

RgbImage read_png(std::span<const std::uint8_t> bytes, const std::string& source_name, PngSourceFormat& source) {
  return read_png(bytes, source_name, source, PngReadOptions{});
}

RgbImage read_png(std::span<const std::uint8_t> bytes, const std::string& source_name, PngSourceFormat& source,
                  const PngReadOptions& options) {
  if (bytes.size() < 8 || png_sig_cmp(bytes.data(), 0, 8) != 0) {
    throw InputError("cannot read PNG '" + source_name + "': not a PNG file (" +
                     (bytes.size() < 8 ? "only " + std::to_string(bytes.size()) + " bytes long"
                                       : std::string("the first 8 bytes are not the PNG signature")) +
                     ")");
  }
  PngContext context;
  context.bytes = bytes.data();
  context.size = bytes.size();
  context.input_bytes = bytes.size();
  context.position = 8;
  return decode_png(context, read_from_memory, source_name, source, options);
}

}  // namespace stridemap::io
