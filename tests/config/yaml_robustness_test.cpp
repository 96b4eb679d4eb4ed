// Text that trips the YAML library itself, found by fuzzing (fuzz/): each
// must be an error naming the file and line, never a hang, a crash or a
// silently empty configuration.
#include <string>

#include <gtest/gtest.h>

#include "stridemap/config/mapper_config.hpp"
#include "stridemap/config/scene_yaml.hpp"
#include "stridemap/config/structured_light_config.hpp"
#include "stridemap/core/error.hpp"

namespace stridemap {
namespace {

// The same text through every YAML reader; returns the three messages.
std::vector<std::string> errors_of(const std::string& text) {
  std::vector<std::string> messages;
  const auto record = [&](auto&& parse) {
    try {
      parse();
      messages.push_back("no error");
    } catch (const InputError& e) {
      messages.push_back(e.what());
    }
  };
  record([&] { parse_scene_yaml(text, "in.yaml"); });
  record([&] { parse_mapper_config(text, "in.yaml"); });
  record([&] { parse_structured_light_config(text, "in.yaml"); });
  return messages;
}

// yaml-cpp 0.7's LoadAll never returns on these, and Load reads them as an
// empty document.
TEST(YamlRobustness, CommaOutsideAFlowCollectionIsAnErrorNotAHang) {
  for (const std::string text : {",", ", x", "  ,\n", "a: 1\n---\n,\n"}) {
    for (const std::string& message : errors_of(text)) {
      EXPECT_EQ(message.rfind("in.yaml:", 0), 0u) << message;
      EXPECT_NE(message.find("not valid YAML: cannot read on from ','"), std::string::npos) << message;
    }
  }
  EXPECT_EQ(errors_of("a: 1\n---\n,\n")[1], "in.yaml:3: not valid YAML: cannot read on from ','");
}

TEST(YamlRobustness, ControlBytesAndDeepNesting) {
  for (const std::string& message : errors_of(std::string("map: {cells_per_side: 1\0\0}", 26))) {
    EXPECT_EQ(message.rfind("in.yaml:1:", 0), 0u) << message;
  }
  const std::string deep = std::string(5000, '[') + std::string(5000, ']');
  for (const std::string& message : errors_of(deep)) {
    EXPECT_EQ(message.rfind("in.yaml:1: not valid YAML", 0), 0u) << message;
  }
}

TEST(YamlRobustness, EmptyAndCommentOnlyFilesStayEmpty) {
  // A mapper config may be empty (all defaults); a scene may not.
  EXPECT_EQ(errors_of("")[1], "no error");
  EXPECT_EQ(errors_of("# nothing here\n")[1], "no error");
  EXPECT_NE(errors_of("")[0], "no error");
}

// Found by the scene_yaml fuzzer: 2 x 2 samples, but the noise lattice
// covering them at a 0.25 m wavelength wanted 4 GB.
TEST(YamlRobustness, CoarseProceduralResolutionCannotAskForAHugeNoiseLattice) {
  const std::string text =
      "terrain:\n  kind: procedural\n  extent: {min_x_m: 0, min_y_m: -0.5, max_x_m: 8, max_y_m: 55}\n"
      "  seed: 12\n  amplitude_m: 0.03\n  wavelength_m: 0.25\n  resolution_m: 5605\n";
  EXPECT_EQ(errors_of(text)[0].rfind("in.yaml:6: terrain.wavelength_m: needs ", 0), 0u) << errors_of(text)[0];
  EXPECT_NE(errors_of(text)[0].find("noise lattice values over the sampled grid, more than the limit of 50000000"),
            std::string::npos);
}

}  // namespace
}  // namespace stridemap
