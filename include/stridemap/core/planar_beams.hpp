#pragma once
// The valid beams of one planar scan, calibrated and packed together: what
// the mapper's fast per-point path (TerrainMapper::integrate) reads. A sensor
// model that knows its beams' directions in advance fills it straight from
// its raw data (sensors/urg04lx.hpp, UrgModel::to_beams), so that a raw
// value is converted once and never stored as a PlanarScan on the way;
// TerrainMapper packs a PlanarScan into one itself.
//
// The arrays are struct-of-arrays so that the geometry of eq. (5)-(7) runs
// over them as vector code; only the first `count` entries are meaningful.
#include <cstddef>
#include <cstdint>
#include <vector>

namespace stridemap {

struct PlanarBeams {
  double time_s = 0.0;
  std::size_t beams = 0;          ///< beams of the scan, valid or not
  std::size_t invalid_range = 0;  ///< as ScanStats::invalid_range
  std::size_t invalid_beam = 0;   ///< as ScanStats::invalid_beam
  std::size_t count = 0;          ///< valid beams: the entries below
  std::vector<double> range_m;        ///< finite, > 0
  std::vector<double> range_error_m;  ///< Delta r: finite, >= 0
  std::vector<double> cos_angle;      ///< cos and sin of the beam's (finite) angle
  std::vector<double> sin_angle;

  /// Room for `beams` entries (front ends write every beam's slot and keep
  /// only the valid ones); grows, never shrinks, so that a steady stream of
  /// scans allocates nothing.
  void prepare(std::size_t beam_count) {
    if (range_m.size() < beam_count) {
      range_m.resize(beam_count);
      range_error_m.resize(beam_count);
      cos_angle.resize(beam_count);
      sin_angle.resize(beam_count);
    }
    beams = beam_count;
    invalid_range = invalid_beam = count = 0;
  }
};

}  // namespace stridemap
