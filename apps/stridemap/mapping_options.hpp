#pragma once
// The options `stridemap live` and `stridemap map` share (docs/cli.md), and
// the checks of a finished run that both make.
#include <string>

#include <CLI/CLI.hpp>

#include "stridemap/live/live_mapping.hpp"
#include "stridemap/live/map_report.hpp"
#include "stridemap/live/map_run_info.hpp"
#include "stridemap/live/scan_mapper.hpp"

namespace stridemap::cli {

struct MappingArgs : MapRunSettings {
  bool report = false;
};

void add_mapping_options(CLI::App& command, MappingArgs& args);

LiveClock parse_clock(const std::string& name);

/// The mapper's options from the shared ones: the configuration, the fixed
/// window, the scan filters and the map to go on from, all checked before
/// any device is opened or output touched.
ScanMapperOptions mapper_options(const MappingArgs& args);

/// The run's information (map_run_info), with the report page among its
/// outputs when --report asks for it.
MapRunInfo run_info(const MappingArgs& args, const std::string& command, const std::string& scans_from);

/// The scans that reached the mapper but were not used there, for the summary line.
std::string rejected_text(const ScanMapper& mapper);

/// Throws RunFailed when the finished run's global map is not all on disk,
/// when it mapped under half its scans, or when it mapped nothing.
void check_finished_run(const ScanMapper& mapper, const ExportedMap& layers, const TimeRange& scans,
                        const TimeRange& poses, const MappingArgs& args, const MapRunChoices& choices);

}  // namespace stridemap::cli
