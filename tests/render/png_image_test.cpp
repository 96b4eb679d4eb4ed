#include "stridemap/render/png_image.hpp"

#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include <csignal>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <vector>

#include "stridemap/core/error.hpp"
#include "stridemap/vision/stripe_detector.hpp"

namespace stridemap::io {
namespace png_image_test {
namespace {

namespace fs = std::filesystem;
using Bytes = std::vector<std::uint8_t>;

// A fresh folder per test, removed afterwards.
class PngImageTest : public ::testing::Test {
 protected:
  void SetUp() override {
    folder_ = fs::temp_directory_path() /
              ("stridemap_png_test_" + std::to_string(::getpid()) + "_" +
               ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(folder_);
    fs::create_directories(folder_);
  }
  void TearDown() override {
    fs::permissions(folder_, fs::perms::owner_all, fs::perm_options::add);
    fs::remove_all(folder_);
  }
  std::string path(const std::string& name) const { return (folder_ / name).string(); }
  std::vector<std::string> folder_entries() const {
    std::vector<std::string> names;
    for (const auto& entry : fs::directory_iterator(folder_)) names.push_back(entry.path().filename().string());
    return names;
  }
  fs::path folder_;
};

RgbImage noise_image(int width, int height, std::uint64_t seed) {
  RgbImage image(width, height);
  std::mt19937_64 generator(seed);
  for (auto& byte : image.rgb) byte = static_cast<std::uint8_t>(generator() & 0xFFU);
  return image;
}

Bytes read_bytes(const std::string& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void write_bytes(const std::string& file, const Bytes& bytes) {
  std::ofstream out(file, std::ios::binary);
  out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
}

template <typename Function>
void expect_input_error(Function&& function, const std::vector<std::string>& fragments) {
  try {
    function();
    ADD_FAILURE() << "no InputError thrown";
  } catch (const InputError& error) {
    const std::string message = error.what();
    for (const auto& fragment : fragments) {
      EXPECT_NE(message.find(fragment), std::string::npos) << "'" << fragment << "' missing from: " << message;
    }
  }
}

// A minimal PNG encoder written from the specification (zlib "stored"
// blocks, no compression), so that read_png is checked against files that
// libpng did not write, in colour types write_png never produces.
std::uint32_t crc32(const Bytes& data, std::size_t begin, std::size_t end) {
  std::uint32_t crc = 0xFFFFFFFFU;
  for (std::size_t i = begin; i < end; ++i) {
    crc ^= data[i];
    for (int bit = 0; bit < 8; ++bit) crc = (crc >> 1) ^ (0xEDB88320U & (0U - (crc & 1U)));
  }
  return crc ^ 0xFFFFFFFFU;
}

void put_u32(Bytes& out, std::uint32_t value) {
  for (int shift = 24; shift >= 0; shift -= 8) out.push_back(static_cast<std::uint8_t>(value >> shift));
}

void put_chunk(Bytes& out, const char* type, const Bytes& data) {
  put_u32(out, static_cast<std::uint32_t>(data.size()));
  const std::size_t start = out.size();
  out.insert(out.end(), type, type + 4);
  out.insert(out.end(), data.begin(), data.end());
  put_u32(out, crc32(out, start, out.size()));
}

// `scanlines` holds each row's bytes without the filter byte.
Bytes handmade_png(std::uint32_t width, std::uint32_t height, std::uint8_t bit_depth, std::uint8_t colour_type,
                   const std::vector<Bytes>& scanlines, const Bytes& palette = {}, const Bytes& transparency = {},
                   std::uint8_t interlace = 0) {
  Bytes raw;
  for (const auto& row : scanlines) {
    raw.push_back(0);  // filter type None
    raw.insert(raw.end(), row.begin(), row.end());
  }
  Bytes zlib = {0x78, 0x01};
  for (std::size_t offset = 0; offset < raw.size(); offset += 65535) {
    const std::size_t length = std::min<std::size_t>(65535, raw.size() - offset);
    zlib.push_back(offset + length == raw.size() ? 1 : 0);
    zlib.push_back(static_cast<std::uint8_t>(length & 0xFF));
    zlib.push_back(static_cast<std::uint8_t>(length >> 8));
    zlib.push_back(static_cast<std::uint8_t>(~length & 0xFF));
    zlib.push_back(static_cast<std::uint8_t>((~length >> 8) & 0xFF));
    zlib.insert(zlib.end(), raw.begin() + static_cast<std::ptrdiff_t>(offset),
                raw.begin() + static_cast<std::ptrdiff_t>(offset + length));
  }
  std::uint32_t a = 1;
  std::uint32_t b = 0;
  for (std::uint8_t byte : raw) {
    a = (a + byte) % 65521U;
    b = (b + a) % 65521U;
  }
  put_u32(zlib, (b << 16) | a);

  Bytes png = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
  Bytes header;
  put_u32(header, width);
  put_u32(header, height);
  header.insert(header.end(), {bit_depth, colour_type, 0, 0, interlace});
  put_chunk(png, "IHDR", header);
  if (!palette.empty()) put_chunk(png, "PLTE", palette);
  if (!transparency.empty()) put_chunk(png, "tRNS", transparency);
  put_chunk(png, "IDAT", zlib);
  put_chunk(png, "IEND", {});
  return png;
}

void expect_pixel(const RgbImage& image, int x, int y, std::uint8_t r, std::uint8_t g, std::uint8_t b) {
  const auto at = image.offset(x, y);
  EXPECT_EQ(image.rgb[at], r) << "x " << x << " y " << y;
  EXPECT_EQ(image.rgb[at + 1], g) << "x " << x << " y " << y;
  EXPECT_EQ(image.rgb[at + 2], b) << "x " << x << " y " << y;
}

TEST_F(PngImageTest, RoundTripKeepsEveryPixel) {
  const RgbImage image = noise_image(37, 23, 7);
  write_png(path("noise.png"), image);
  const RgbImage back = read_png(path("noise.png"));
  EXPECT_EQ(back.width, 37);
  EXPECT_EQ(back.height, 23);
  EXPECT_EQ(back.rgb, image.rgb);
  EXPECT_EQ(folder_entries(), std::vector<std::string>{"noise.png"}) << "temporary file left behind";
}

TEST_F(PngImageTest, OverwritesAnExistingFile) {
  write_png(path("a.png"), RgbImage(4, 4, 10, 20, 30));
  write_png(path("a.png"), RgbImage(2, 3, 200, 100, 0));
  const RgbImage back = read_png(path("a.png"));
  EXPECT_EQ(back.width, 2);
  EXPECT_EQ(back.height, 3);
  expect_pixel(back, 1, 2, 200, 100, 0);
}

TEST_F(PngImageTest, ReportsTheFilesColourTypeAndTheStripeReaderNeedsColour) {
  write_bytes(path("gray.png"), handmade_png(2, 1, 8, 0, {{0, 200}}));
  PngSourceFormat format;
  read_png(path("gray.png"), format);
  EXPECT_FALSE(format.has_colour);
  EXPECT_EQ(format.colour_type, "grey");
  try {
    read_stripe_image(path("gray.png"), 2, 1);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("gray.png: a grey PNG has no colour"), std::string::npos) << e.what();
  }
  write_bytes(path("palette.png"), handmade_png(3, 1, 8, 3, {{2, 0, 1}}, {255, 0, 0, 0, 255, 0, 0, 0, 255}));
  read_png(path("palette.png"), format);
  EXPECT_TRUE(format.has_colour);
  EXPECT_EQ(format.colour_type, "palette");
  EXPECT_EQ(read_stripe_image(path("palette.png"), 3, 1).width, 3);
  try {
    read_stripe_image(path("palette.png"), 640, 480);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("the image is 3 x 1 pixels, the configuration describes a 640 x 480"),
              std::string::npos)
        << e.what();
  }
}

TEST_F(PngImageTest, ReadsGrayPaletteAlphaAndSixteenBitFiles) {
  write_bytes(path("gray.png"), handmade_png(2, 1, 8, 0, {{0, 200}}));
  RgbImage image = read_png(path("gray.png"));
  expect_pixel(image, 0, 0, 0, 0, 0);
  expect_pixel(image, 1, 0, 200, 200, 200);

  // 1-bit gray: 8 pixels in one byte, 1 = white.
  write_bytes(path("gray1.png"), handmade_png(8, 1, 1, 0, {{0b10000001}}));
  image = read_png(path("gray1.png"));
  expect_pixel(image, 0, 0, 255, 255, 255);
  expect_pixel(image, 1, 0, 0, 0, 0);
  expect_pixel(image, 7, 0, 255, 255, 255);

  // Palette with a transparent entry: colour kept, alpha dropped.
  write_bytes(path("palette.png"), handmade_png(3, 1, 8, 3, {{2, 0, 1}}, {255, 0, 0, 0, 255, 0, 0, 0, 255}, {0}));
  image = read_png(path("palette.png"));
  expect_pixel(image, 0, 0, 0, 0, 255);
  expect_pixel(image, 1, 0, 255, 0, 0);
  expect_pixel(image, 2, 0, 0, 255, 0);

  write_bytes(path("rgba.png"), handmade_png(1, 2, 8, 6, {{10, 20, 30, 0}, {40, 50, 60, 255}}));
  image = read_png(path("rgba.png"));
  expect_pixel(image, 0, 0, 10, 20, 30);
  expect_pixel(image, 0, 1, 40, 50, 60);

  write_bytes(path("gray_alpha.png"), handmade_png(1, 1, 8, 4, {{77, 128}}));
  expect_pixel(read_png(path("gray_alpha.png")), 0, 0, 77, 77, 77);

  // 16-bit RGB keeps the high byte.
  write_bytes(path("rgb16.png"), handmade_png(1, 1, 16, 2, {{0x12, 0x34, 0xAB, 0xCD, 0xFF, 0x00}}));
  expect_pixel(read_png(path("rgb16.png")), 0, 0, 0x12, 0xAB, 0xFF);
}

TEST_F(PngImageTest, RejectsBadImagesBeforeCreatingAFile) {
  expect_input_error([&] { write_png(path("empty.png"), RgbImage{}); },
                     {"empty.png", "bad image dimensions 0 x 0"});
  RgbImage short_buffer(4, 4);
  short_buffer.rgb.resize(10);
  expect_input_error([&] { write_png(path("short.png"), short_buffer); }, {"short.png", "10 bytes", "needs 48"});
  EXPECT_TRUE(folder_entries().empty());
}

TEST_F(PngImageTest, WriteIntoMissingFolderNamesIt) {
  const std::string target = path("no/such/folder/map.png");
  expect_input_error([&] { write_png(target, RgbImage(2, 2)); }, {target, "does not exist"});
}

TEST_F(PngImageTest, WriteBelowAFileSaysItIsNotAFolder) {
  write_bytes(path("plain.txt"), {'x'});
  expect_input_error([&] { write_png(path("plain.txt/map.png"), RgbImage(2, 2)); }, {"plain.txt", "not a folder"});
}

TEST_F(PngImageTest, WriteIntoReadOnlyFolder) {
  const fs::path locked = folder_ / "locked";
  fs::create_directories(locked);
  fs::permissions(locked, fs::perms::owner_read | fs::perms::owner_exec, fs::perm_options::replace);
  if (::access(locked.c_str(), W_OK) == 0) {
    GTEST_SKIP() << "running with privileges that can write into a read-only folder (e.g. root)";
  }
  expect_input_error([&] { write_png((locked / "map.png").string(), RgbImage(2, 2)); }, {"locked", "not writable"});
}

// A file-size limit makes the kernel refuse writes the way a full disk does.
TEST_F(PngImageTest, FailedWriteLeavesNoHalfFileAndKeepsTheOldOne) {
  const std::string target = path("map.png");
  write_png(target, RgbImage(3, 3, 1, 2, 3));
  const Bytes before = read_bytes(target);

  rlimit old_limit{};
  ASSERT_EQ(::getrlimit(RLIMIT_FSIZE, &old_limit), 0);
  const auto old_handler = std::signal(SIGXFSZ, SIG_IGN);
  rlimit small = old_limit;
  small.rlim_cur = 4096;
  ASSERT_EQ(::setrlimit(RLIMIT_FSIZE, &small), 0);
  bool threw = false;
  std::string message;
  try {
    write_png(target, noise_image(300, 300, 3));  // noise does not compress: ~270 kB
  } catch (const InputError& error) {
    threw = true;
    message = error.what();
  }
  ::setrlimit(RLIMIT_FSIZE, &old_limit);
  std::signal(SIGXFSZ, old_handler);

  ASSERT_TRUE(threw);
  EXPECT_NE(message.find(target), std::string::npos) << message;
  EXPECT_NE(message.find("write failed"), std::string::npos) << message;
  EXPECT_EQ(read_bytes(target), before);
  EXPECT_EQ(folder_entries(), std::vector<std::string>{"map.png"}) << "temporary file left behind";
}

TEST_F(PngImageTest, ReadErrorsNameTheFileAndTheProblem) {
  expect_input_error([&] { read_png(path("missing.png")); }, {"missing.png", "does not exist"});

  write_bytes(path("text.png"), {'h', 'e', 'l', 'l', 'o', ' ', 'w', 'o', 'r', 'l', 'd'});
  expect_input_error([&] { read_png(path("text.png")); }, {"text.png", "not a PNG"});
  write_bytes(path("tiny.png"), {0x89, 'P'});
  expect_input_error([&] { read_png(path("tiny.png")); }, {"tiny.png", "not a PNG", "only 2 bytes"});
  expect_input_error([&] { read_png(folder_.string()); }, {folder_.string(), "read failed"});
}

TEST_F(PngImageTest, TruncatedFileIsReportedNotCrashed) {
  write_png(path("full.png"), noise_image(64, 64, 11));
  const Bytes full = read_bytes(path("full.png"));
  for (const std::size_t keep : {std::size_t{20}, std::size_t{40}, full.size() / 2, full.size() - 5}) {
    write_bytes(path("cut.png"), Bytes(full.begin(), full.begin() + static_cast<std::ptrdiff_t>(keep)));
    expect_input_error([&] { read_png(path("cut.png")); }, {"cut.png", "truncated"});
  }
}

TEST_F(PngImageTest, CorruptedDataIsReported) {
  write_png(path("good.png"), noise_image(16, 16, 5));
  Bytes bytes = read_bytes(path("good.png"));
  bytes[bytes.size() / 2] ^= 0x5A;  // inside IDAT: its CRC no longer matches
  write_bytes(path("bad.png"), bytes);
  expect_input_error([&] { read_png(path("bad.png")); }, {"bad.png", "corrupted"});
}

TEST_F(PngImageTest, BadHeaderDimensionsAreReported) {
  write_bytes(path("zero.png"), handmade_png(0, 1, 8, 0, {{}}));
  expect_input_error([&] { read_png(path("zero.png")); }, {"zero.png", "corrupted"});
  // A header claiming 10^10 pixels must not make the reader allocate them.
  write_bytes(path("huge.png"), handmade_png(100000, 100000, 8, 0, {{0}}));
  expect_input_error([&] { read_png(path("huge.png")); }, {"huge.png", "100000 x 100000", "exceed the limit"});
}

// 16000 x 16000 pixels within the limit, but only one row of data: reading
// must fail at the data, without first taking the 768 MB the header claims.
TEST_F(PngImageTest, ATinyFileClaimingAHugeImageDoesNotAllocateIt) {
  write_bytes(path("bomb.png"), handmade_png(16000, 16000, 8, 0, {Bytes(16000, 7)}));
  rusage before{};
  ::getrusage(RUSAGE_SELF, &before);
  expect_input_error([&] { read_png(path("bomb.png")); }, {"bomb.png", "Not enough image data"});
  rusage after{};
  ::getrusage(RUSAGE_SELF, &after);
  EXPECT_LT(after.ru_maxrss - before.ru_maxrss, 64L * 1024) << "peak resident memory grew by "
                                                            << (after.ru_maxrss - before.ru_maxrss) << " kB";
}

// A reader that knows the size it wants (a camera configuration) checks the
// header before a single row is decoded: the claim of 16000 x 16000 is
// refused for its size, not for the data it lacks further on.
TEST_F(PngImageTest, ExpectedSizeAndPixelLimitAreCheckedFromTheHeaderBeforeDecoding) {
  write_bytes(path("bomb.png"), handmade_png(16000, 16000, 8, 2, {Bytes(48000, 7)}));
  PngSourceFormat format;
  int seen_width = 0, seen_height = 0;
  PngReadOptions options;
  options.check_header = [&](int width, int height, const PngSourceFormat& source) {
    seen_width = width;
    seen_height = height;
    EXPECT_EQ(source.colour_type, "RGB");
    if (width != 640 || height != 480) throw InputError("bomb.png: not the 640 x 480 the config says");
  };
  expect_input_error([&] { read_png(path("bomb.png"), format, options); }, {"not the 640 x 480 the config says"});
  EXPECT_EQ(seen_width, 16000);
  EXPECT_EQ(seen_height, 16000);

  PngReadOptions small;
  small.max_pixels = 1000 * 1000;
  expect_input_error([&] { read_png(path("bomb.png"), format, small); },
                     {"bomb.png", "16000 x 16000 exceed the limit of 1000000 pixels"});

  // The stripe detector reads camera frames this way.
  expect_input_error([&] { read_stripe_image(path("bomb.png"), 640, 480); },
                     {"bomb.png: the image is 16000 x 16000 pixels, the configuration describes a 640 x 480"});
  // A file of the expected size is read as before.
  RgbImage frame(4, 3, 200, 10, 10);
  write_png(path("frame.png"), frame);
  EXPECT_EQ(read_png(path("frame.png"), format, small).width, 4);
  EXPECT_EQ(read_stripe_image(path("frame.png"), 4, 3).height, 3);
}

// Interlaced images are decoded whole, so the size check comes first: the
// header's image must fit what the file's bytes can inflate to.
TEST_F(PngImageTest, AnInterlacedFileTooShortForItsImageIsRefusedBeforeAllocating) {
  write_bytes(path("one_pixel.png"), handmade_png(1, 1, 8, 0, {Bytes{200}}, {}, {}, 1));
  const RgbImage pixel = read_png(path("one_pixel.png"));
  ASSERT_EQ(pixel.width, 1);
  expect_pixel(pixel, 0, 0, 200, 200, 200);

  const Bytes bomb = handmade_png(16000, 16000, 8, 2, {Bytes(48000, 7)}, {}, {}, 1);
  write_bytes(path("bomb.png"), bomb);
  rusage before{};
  ::getrusage(RUSAGE_SELF, &before);
  expect_input_error([&] { read_png(path("bomb.png")); },
                     {"bomb.png", "interlaced 16000 x 16000 image needs at least 744186 bytes of compressed data",
                      "the whole file has " + std::to_string(bomb.size())});
  expect_input_error([&] { read_png(bomb, "frame.png"); }, {"frame.png", "744186 bytes"});
  rusage after{};
  ::getrusage(RUSAGE_SELF, &after);
  EXPECT_LT(after.ru_maxrss - before.ru_maxrss, 64L * 1024) << "peak resident memory grew by "
                                                            << (after.ru_maxrss - before.ru_maxrss) << " kB";
}

}  // namespace
}  // namespace png_image_test
}  // namespace stridemap::io
