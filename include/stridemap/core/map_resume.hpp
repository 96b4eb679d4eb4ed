#pragma once
// Going on mapping from a saved map (mapfile/map_file.hpp): the mapper takes the
// saved map's every layer, window position included, and integrates the
// next scans into it exactly as if it had never stopped, except that the
// first scan after resuming has no previous scan to measure motion from
// unless the caller passes the last scan's pose and time.
#include <optional>

#include "stridemap/core/grid_map.hpp"
#include "stridemap/core/pose.hpp"
#include "stridemap/core/terrain_mapper.hpp"

namespace stridemap {

/// Replaces the mapper's map with `saved`, layer by layer by name into the
/// mapper's own layer registry, so that LayerIds taken from the mapper's map
/// stay valid; a layer only the file holds is added, one only the mapper
/// declared starts from its reset value. Throws InputError when the mapper's
/// grid (cells per side, cell size) is not the saved map's, or a layer of
/// the same name holds another type: the options must describe the map
/// being continued.
void resume_from_map(TerrainMapper& mapper, const ElevationMap& saved);

/// The same, and the mapper remembers the last scan integrated into the
/// saved map (its pose and time, when known): the next scan's motion and
/// its order check then come out as in a run that never stopped. The
/// mapper's totals() count that as one scan of no beams.
void resume_from_map(TerrainMapper& mapper, const ElevationMap& saved, std::optional<TrunkPose> last_pose,
                     std::optional<double> last_scan_time_s);

/// The mapper options with the saved map's grid, for a caller that wants
/// the map's own geometry rather than the configuration's.
MapperOptions options_for_map(MapperOptions options, const ElevationMap& saved);

}  // namespace stridemap
