#pragma once
// Raw URG scans from a recording, for the emulator to replay: a stridemap
// scan log (recordings/scan_log.hpp), or the BreezySLAM text logs of real URG-04LX
// scans (one scan per line: token 0 the time in microseconds, tokens 1-23
// other robot fields, then the raw values of steps 44.. in millimetres with
// the sensor's error codes).
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace stridemap::io {

struct RecordedScans {
  std::string format;  ///< "stridemap" or "breezyslam"
  std::vector<std::vector<std::uint32_t>> scans;
  int first_step = 44;
  int cluster = 1;
};

/// BreezySLAM: every line must hold 24 + `values_per_scan` whole numbers
/// (683 in the published logs); InputError "<file>:<line>: ..." otherwise.
RecordedScans read_breezyslam_scans(const std::string& path, std::size_t values_per_scan = 683);
/// The same from the recording's bytes; `source_name` stands for the file.
RecordedScans parse_breezyslam_scans(std::string_view text, const std::string& source_name,
                                     std::size_t values_per_scan = 683);

/// A stridemap scan log (first line "stridemap-urg-log") or else a
/// BreezySLAM log. A damaged scan log gives the scans before the damage.
RecordedScans read_recorded_scans(const std::string& path);
RecordedScans parse_recorded_scans(std::string_view text, const std::string& source_name);

}  // namespace stridemap::io
