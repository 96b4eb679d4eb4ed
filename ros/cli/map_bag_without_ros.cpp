// `stridemap map --bag` in a tool built without ROS: the options are there
// (map_bag_options.cpp, so scripts get a clear message, not "unknown
// option") and running says why it cannot.
#include "map_bag.hpp"

#include "stridemap/core/error.hpp"

namespace stridemap::cli {

void run_map_bag(const MapBagArgs& args, const std::string&, const std::string&) {
  throw InputError("--bag " + args.bag_path +
                   ": this stridemap was built without ROS (configure with the ROS packages installed and "
                   "-DSTRIDEMAP_WITH_ROS=ON; docs/ros.md)");
}

}  // namespace stridemap::cli
