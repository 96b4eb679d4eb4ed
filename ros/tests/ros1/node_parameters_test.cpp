// The nodes' parameter reader on a table: what roscpp's param() would take
// silently (a string for a number, a typo'd name) is refused by name.
#include <gtest/gtest.h>

#include "stridemap/core/error.hpp"
#include "stridemap_ros/node_parameters.hpp"

namespace stridemap::ros_adapter {
namespace node_parameters_test {
namespace {

TEST(NodeParameters, AnIntegerIsANumberAndDefaultsStandWhereNothingIsSet) {
  const TableParameters table({{"rate_hz", XmlRpc::XmlRpcValue(5)}});
  ParameterReader read(table);
  EXPECT_EQ(read.number("rate_hz", 1.0, 0.0, 10.0, "rate"), 5.0);
  EXPECT_EQ(read.number("wait_s", 0.5, 0.0, 10.0, "wait"), 0.5);
  EXPECT_EQ(read.text("frame", "map", "frame"), "map");
  EXPECT_NO_THROW(read.refuse_unknown());
  EXPECT_EQ(read.summary(), "rate_hz=5 wait_s=0.5 frame='map'");
}

TEST(NodeParameters, WrongTypesRangesAndNamesAreRefusedByName) {
  const TableParameters table({{"wait_s", XmlRpc::XmlRpcValue(std::string("abc"))},
                               {"count", XmlRpc::XmlRpcValue(2.5)},
                               {"rate_hz", XmlRpc::XmlRpcValue(1e9)},
                               {"wiat_s", XmlRpc::XmlRpcValue(1.0)}});
  ParameterReader read(table);
  EXPECT_THROW(read.number("wait_s", 0.5, 0.0, 10.0, ""), InputError);
  EXPECT_THROW(read.integer("count", 1, 1, 10, ""), InputError);
  try {
    read.number("rate_hz", 1.0, 0.0, 10.0, "");
    ADD_FAILURE() << "1e9 taken";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("~rate_hz: 1e+09 is outside [0, 10]"), std::string::npos) << e.what();
  }
  try {
    read.refuse_unknown();
    ADD_FAILURE() << "an unknown name taken";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("~wiat_s"), std::string::npos) << e.what();
  }
}

TEST(NodeParameters, RelativePathsAreUnderTheBaseAndEmptyStaysEmpty) {
  const TableParameters table({{"map_file", XmlRpc::XmlRpcValue(std::string("maps/run.smap"))},
                               {"abs", XmlRpc::XmlRpcValue(std::string("/data/x.yaml"))}});
  ParameterReader read(table);
  EXPECT_EQ(read.path("map_file", "", "/home/u/.ros", ""), "/home/u/.ros/maps/run.smap");
  EXPECT_EQ(read.path("abs", "", "/home/u/.ros", ""), "/data/x.yaml");
  EXPECT_EQ(read.path("config", "", "/home/u/.ros", ""), "");
}

}  // namespace
}  // namespace node_parameters_test
}  // namespace stridemap::ros_adapter
