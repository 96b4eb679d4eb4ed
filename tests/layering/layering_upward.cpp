// Built by the test layering_upward_include, which expects the build to FAIL:
// this program links only stridemap::core, so the io header below must not be
// found. If it compiles, a layer can see headers above it again.
#include "stridemap/core/grid_map.hpp"
#include "stridemap/io/grid_csv.hpp"

int main() { return stridemap::ElevationMap().cells_per_side() == 100 ? 0 : 1; }
