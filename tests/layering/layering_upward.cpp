// Built by the test layering_upward_include, which expects the build to FAIL:
// this program links only stridemap::core, so the mapfile header below must not be
// found. If it compiles, a layer can see headers above it again.
#include "stridemap/core/grid_map.hpp"
#include "stridemap/mapfile/grid_csv.hpp"

int main() { return stridemap::ElevationMap().cells_per_side() == 100 ? 0 : 1; }
