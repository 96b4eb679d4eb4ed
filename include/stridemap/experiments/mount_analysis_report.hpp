#pragma once
// Outputs of the mount analysis: a heat map per metric over the sweep
// (height across, pitch up, the best mount framed), the sweep as CSV,
// summary.json (shape in docs/experiments.md) and the printed table.
#include <string>

#include "stridemap/experiments/mount_analysis.hpp"

namespace stridemap {

std::string mount_analysis_summary_json(const MountAnalysisResult& result, const MountAnalysisOptions& options);
std::string mount_analysis_table(const MountAnalysisResult& result);
void write_mount_analysis_outputs(const MountAnalysisResult& result, const MountAnalysisOptions& options,
                                  const std::string& directory);

}  // namespace stridemap
