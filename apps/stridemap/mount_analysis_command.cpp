// `stridemap experiment mount-analysis`: placeholder registration until the
// analysis lands (replaced below in this branch).
#include "walk_cli_common.hpp"

namespace stridemap::cli {

WalkSensorFactory structured_light_walk_sensor_factory(std::uint64_t) {
  throw InputError("--sensor structured-light: the structured-light simulator (issue 4) is not in this build yet; use urg");
}

void register_mount_analysis(CLI::App*) {}

}  // namespace stridemap::cli
