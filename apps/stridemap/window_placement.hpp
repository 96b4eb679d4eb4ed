#pragma once
// `map --window` / `live --window` (docs/cli.md): the tool's side of
// live/map_window.hpp.
#include <string>

#include "stridemap/core/pose_track.hpp"
#include "stridemap/live/live_mapping.hpp"
#include "stridemap/live/map_window.hpp"
#include "stridemap/live/scan_mapper.hpp"
#include "stridemap/recordings/scan_log.hpp"

namespace stridemap::cli {

/// A window that stays put instead of following the robot.
void fix_window(ScanMapperOptions& options, const WindowPlacement& placement);

/// --window fit: a first pass over the log (streamed, as the mapping pass
/// reads it) finds where every point the run maps lands; the window is fixed
/// over all of them (said on stderr unless --quiet). Throws GridSizeError
/// when the run needs too large a map, InputError as reading the log does.
void fit_window(ScanMapperOptions& options, const std::string& log_path, const std::string& poses_path,
                double max_pose_gap_s, LiveClock clock);

}  // namespace stridemap::cli
