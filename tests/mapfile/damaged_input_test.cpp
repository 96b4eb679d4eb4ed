// Every shipped input file cut short at many places, and the map file
// format with bytes overwritten: each reader must either read what is there
// or throw an InputError naming the file, never anything else. (The fuzz
// targets do the same with far more inputs; this runs in every `make test`.)
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "stridemap/config/calibration_csv.hpp"
#include "stridemap/config/mapper_config.hpp"
#include "stridemap/config/scene_yaml.hpp"
#include "stridemap/config/structured_light_config.hpp"
#include "stridemap/core/error.hpp"
#include "stridemap/mapfile/grid_csv.hpp"
#include "stridemap/render/png_image.hpp"
#include "test_paths.hpp"

namespace stridemap {
namespace {

namespace fs = std::filesystem;
const fs::path kRoot(STRIDEMAP_SOURCE_DIR);

std::string read_all(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

using Reader = std::function<void(const std::string& bytes)>;

struct Outcome {
  int read = 0;      // the damaged text still read as a valid file
  int rejected = 0;  // InputError naming the source
};

// Feeds `bytes` to the reader; fails the test on any other outcome.
void expect_read_or_named_error(const Reader& reader, const std::string& bytes, const std::string& what,
                                Outcome& outcome) {
  try {
    reader(bytes);
    ++outcome.read;
  } catch (const InputError& e) {
    ++outcome.rejected;
    EXPECT_NE(std::string(e.what()).find("damaged."), std::string::npos) << what << ": " << e.what();
  } catch (const std::exception& e) {
    ADD_FAILURE() << what << ": " << typeid(e).name() << ": " << e.what();
  }
}

struct Format {
  std::vector<fs::path> files;
  Reader reader;
};

std::vector<Format> formats() {
  return {
      {{kRoot / "scenes/cart_rail_boxes.yaml", kRoot / "scenes/thin_edges.yaml", kRoot / "scenes/soak_circuit.yaml"},
       [](const std::string& t) { parse_scene_yaml(t, "damaged.yaml"); }},
      {{kRoot / "configs/urg_messor.yaml"}, [](const std::string& t) { parse_mapper_config(t, "damaged.yaml"); }},
      {{kRoot / "configs/ragno_structured_light.yaml", kRoot / "configs/fig3_structured_light.yaml"},
       [](const std::string& t) { parse_structured_light_config(t, "damaged.yaml"); }},
      {{kRoot / "configs/urg_calibration_example.csv"},
       [](const std::string& t) {
         std::istringstream in(t);
         read_range_pairs_csv(in, "damaged.csv");
       }},
      {{kRoot / "fuzz/corpus/grid_csv/elevation.csv"},
       [](const std::string& t) {
         std::istringstream in(t);
         io::read_grid_csv(in, "damaged.csv");
       }},
      {{kRoot / "fuzz/corpus/png_image/rgb_4x3.png", kRoot / "fuzz/corpus/png_image/gray_interlaced_3x3.png"},
       [](const std::string& t) {
         io::read_png({reinterpret_cast<const std::uint8_t*>(t.data()), t.size()}, "damaged.png");
       }},
  };
}

TEST(DamagedInput, EveryShippedFileCutShortIsReadOrRejectedByName) {
  for (const Format& format : formats()) {
    for (const fs::path& file : format.files) {
      const std::string bytes = read_all(file);
      ASSERT_FALSE(bytes.empty()) << file;
      Outcome outcome;
      const std::size_t step = std::max<std::size_t>(1, bytes.size() / 300);
      for (std::size_t length = 0; length < bytes.size(); length += step) {
        expect_read_or_named_error(format.reader, bytes.substr(0, length), file.string() + " cut to " +
                                   std::to_string(length) + " bytes", outcome);
      }
      EXPECT_GT(outcome.rejected, 0) << file << ": no cut was noticed";
    }
  }
}

// PNG and grid CSV are what the project reads back of its own outputs.
TEST(DamagedInput, MapFilesWithBytesOverwrittenAreReadOrRejectedByName) {
  const std::vector<Format> all = formats();
  for (const Format& format : {all[4], all[5]}) {
    for (const fs::path& file : format.files) {
      const std::string original = read_all(file);
      Outcome outcome;
      for (std::size_t at = 0; at < original.size(); ++at) {
        for (const char replacement : {'\0', '9', ',', '\n', '\xff'}) {
          std::string bytes = original;
          bytes[at] = replacement;
          expect_read_or_named_error(format.reader, bytes, file.string() + " with byte " + std::to_string(at) +
                                     " overwritten", outcome);
        }
      }
      EXPECT_GT(outcome.rejected, 0) << file;
    }
  }
}

}  // namespace
}  // namespace stridemap
