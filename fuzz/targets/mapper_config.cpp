// Mapper configuration files. The reader names the line of every problem;
// so whatever it accepts the mapper, the fill-in and the sensor model must
// accept too (an error there would come without a line).
#include <string>

#include "fuzz_target.hpp"
#include "stridemap/config/mapper_config.hpp"
#include "stridemap/core/error.hpp"
#include "stridemap/core/weighted_median_fill.hpp"
#include "stridemap/sensors/urg04lx.hpp"

STRIDEMAP_FUZZ_TARGET(mapper_config) {
  using namespace stridemap;
  MapperConfig config;
  try {
    config = parse_mapper_config(std::string(fuzz::as_text(data)), "fuzz.yaml");
  } catch (const InputError&) {
    return;
  }
  // Up to 4096 cells per side are valid, but 335 MB per input is not for a fuzzer.
  if (config.mapper.grid.cells_per_side > 300) config.mapper.grid.cells_per_side = 300;
  try {
    TerrainMapper mapper(config.mapper, config.mount);
    WeightedMedianFill fill(config.fill);
    const UrgModel urg(UrgParameters{}, config.calibration);
    UrgRawScan raw;
    raw.values_mm.assign(static_cast<std::size_t>(urg.parameters().beam_count()), 800);
    PlanarScan scan;
    urg.to_planar_scan(raw, scan);
    mapper.integrate(scan, TrunkPose{});
    fill.apply(mapper.map());
  } catch (const InputError& e) {
    fuzz::failure(std::string("the reader accepted a configuration the library rejects: ") + e.what());
  }
}
