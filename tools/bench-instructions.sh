#!/usr/bin/env bash
# Instructions per valid point of the per-point path (raw millimetres ->
# calibrated beams -> the map), counted by callgrind over a fixed workload
# (bench/point_path_workload.cpp: 750 URG scans, 1 cm cells, 100 x 100),
# split into the conversion, the integration and the rest (the pipeline's
# modes: filters, bookkeeping, foothold layers). Instruction counts do not
# depend on the machine's load, unlike times. Usage:
#   tools/bench-instructions.sh [build-dir] [scans]
set -euo pipefail
build_dir=${1:-build}
scans=${2:-750}
program="$build_dir/bin/point_path_workload"
command -v valgrind >/dev/null || { echo "bench-instructions: valgrind is not installed (apt-get install valgrind)" >&2; exit 1; }
[ -x "$program" ] || { echo "bench-instructions: $program is missing; build the point_path_workload target" >&2; exit 1; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# Inclusive instructions of the first function whose name matches $2 in
# the callgrind output $1.
inclusive() {
  callgrind_annotate --inclusive=yes --threshold=100 "$1" 2>/dev/null |
    awk -v pattern="$2" '!found && index($0, pattern) { gsub(",", "", $1); print $1; found = 1 }'
}

# The pipeline first: it is what the tool, live, Python and ROS run.
for mode in pipeline pipeline-paper pipeline-foothold packed planar; do
  out="$work/callgrind.$mode"
  valgrind --tool=callgrind --callgrind-out-file="$out" "$program" "$mode" "$scans" >"$work/stdout.$mode" 2>/dev/null
  points=$(awk '{print $4}' "$work/stdout.$mode")
  total=""
  case "$mode" in
    packed)
      conversion=$(inclusive "$out" "UrgModel::to_beams(")
      integration=$(inclusive "$out" "TerrainMapper::integrate(stridemap::PlanarBeams const&")
      label="packed (UrgModel::to_beams + TerrainMapper::integrate(PlanarBeams))" ;;
    planar)
      conversion=$(inclusive "$out" "UrgModel::to_planar_scan(")
      integration=$(inclusive "$out" "TerrainMapper::integrate(stridemap::PlanarScan const&")
      label="planar (UrgModel::to_planar_scan + TerrainMapper::integrate(PlanarScan))" ;;
    pipeline|pipeline-paper)
      [ "$mode" = pipeline ] && conversion=$(inclusive "$out" "UrgModel::to_beams(") ||
        conversion=$(inclusive "$out" "UrgModel::to_planar_scan(")
      integration=$(inclusive "$out" "TerrainMapper::integrate(stridemap::Planar")
      total=$(inclusive "$out" "ScanIntegrator::push(stridemap::UrgRawScan const&")
      [ "$mode" = pipeline ] && label="pipeline as run by default: no scan filters, foothold layers when read (ScanIntegrator::push)" ||
        label="pipeline, the paper's scan filters (ScanIntegrator::push)" ;;
    pipeline-foothold)
      conversion=$(inclusive "$out" "UrgModel::to_beams(")
      integration=$(inclusive "$out" "TerrainMapper::integrate(stridemap::PlanarBeams const&")
      total=$(inclusive "$out" "MappingPipeline::add(stridemap::UrgRawScan const&")
      label="pipeline, foothold layers every scan (update_every_scan; MappingPipeline::add)" ;;
  esac
  awk -v label="$label" -v scans="$scans" -v points="$points" -v c="${conversion:-0}" -v i="${integration:-0}" \
      -v t="${total:-0}" 'BEGIN {
    if (t == 0) t = c + i
    printf "%s\n  %d scans, %d valid points: %.1f instructions per valid point (conversion %.1f, integration %.1f, the rest %.1f)\n",
      label, scans, points, t / points, c / points, i / points, (t - c - i) / points }'
done
