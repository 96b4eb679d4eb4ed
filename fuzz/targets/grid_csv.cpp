// Map layers read back from grid CSV files (the project's map file format):
// a grid that reads must have the shape its header claims.
#include <sstream>
#include <string>

#include "fuzz_target.hpp"
#include "stridemap/core/error.hpp"
#include "stridemap/mapfile/grid_csv.hpp"

STRIDEMAP_FUZZ_TARGET(grid_csv) {
  using namespace stridemap;
  std::istringstream input{std::string(fuzz::as_text(data))};
  try {
    io::GridCsvOptions metadata;
    const Eigen::MatrixXf grid = io::read_grid_csv(input, "fuzz.csv", &metadata);
    fuzz::check(grid.rows() > 0 && grid.cols() > 0, "an empty grid was accepted");
  } catch (const InputError&) {
  }
}
