// Every enum read or written as text has one name table: the words are the
// ones configs, options and summary.json have always used, each word reads
// back to its value, and an unknown word is refused with the valid ones.
#include <string>
#include <string_view>

#include <gtest/gtest.h>

#include "stridemap/core/enum_names.hpp"
#include "stridemap/core/error.hpp"
#include "stridemap/core/map_update.hpp"
#include "stridemap/experiments/cart_rail.hpp"
#include "stridemap/sim/pose_estimate.hpp"

namespace stridemap {
namespace {

template <typename Enum, std::size_t N>
void expect_round_trip(const EnumNameTable<Enum, N>& table) {
  for (const auto& [value, word] : table) {
    EXPECT_EQ(name(value), word);
    EXPECT_EQ(parse_enum_name<Enum>(word), value) << word;
  }
}

template <typename Enum>
std::string error_of(std::string_view word) {
  try {
    parse_enum_name<Enum>(word);
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

TEST(EnumNames, TheWordsAreTheOnesOutputsAlwaysUsed) {
  EXPECT_EQ(name(ElevationRule::paper_highest), "paper");
  EXPECT_EQ(name(ElevationRule::gated_highest), "gated");
  EXPECT_EQ(name(SimulatedSensor::urg), "urg");
  EXPECT_EQ(name(SimulatedSensor::structured_light), "structured-light");
  EXPECT_EQ(name(StripePipeline::image), "image");
  EXPECT_EQ(name(StripePipeline::geometric), "geometric");
  EXPECT_EQ(name(ReferenceElevationSource::map), "map");
  EXPECT_EQ(name(ReferenceElevationSource::map_mean), "map-mean");
  EXPECT_EQ(name(ReferenceElevationSource::truth), "truth");
  EXPECT_EQ(name(ReferenceElevationSource::map_fused), "map-fused");
  EXPECT_EQ(name(ReferenceElevationSource::legs), "legs");
  EXPECT_EQ(name(ReferenceElevationSource::map_footholds), "map-footholds");
}

TEST(EnumNames, EveryWordReadsBackToItsValue) {
  expect_round_trip(kElevationRuleNames);
  expect_round_trip(kSimulatedSensorNames);
  expect_round_trip(kStripePipelineNames);
  expect_round_trip(kReferenceElevationSourceNames);
}

TEST(EnumNames, AnUnknownWordIsRefusedWithTheValidOnes) {
  EXPECT_EQ(error_of<ElevationRule>("newest"), "'newest' is not an elevation rule; expected one of: paper, gated");
  EXPECT_EQ(error_of<SimulatedSensor>("lidar"), "'lidar' is not a sensor; expected one of: urg, structured-light");
  EXPECT_EQ(error_of<StripePipeline>("Image"), "'Image' is not a pipeline; expected one of: image, geometric");
  EXPECT_EQ(error_of<ReferenceElevationSource>(""),
            "'' is not a reference elevation source; expected one of: map, map-mean, truth, map-fused, legs, "
            "map-footholds");
}

TEST(EnumNames, AValueOutsideTheTableIsNamedUnknown) {
  EXPECT_EQ(name(static_cast<ElevationRule>(200)), "unknown");
}

}  // namespace
}  // namespace stridemap
