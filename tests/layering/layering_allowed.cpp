// Built by the test layering_allowed_include: a program that links only
// stridemap::core and includes core headers compiles.
#include "stridemap/core/grid_map.hpp"

int main() { return stridemap::ElevationMap().cells_per_side() == 100 ? 0 : 1; }
