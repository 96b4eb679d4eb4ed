#pragma once
// Importers: other formats turned into stridemap's own scan log
// (recordings/scan_log.hpp) and pose file (recordings/pose_stream.hpp), so that recorded
// data of any origin goes through the one mapping entry point,
// `stridemap map --log --poses` (docs/import.md has a worked example of
// each). Every malformed line, and every record whose time breaks the
// increasing order, is skipped, counted and reported as
// "<file>:<line>: <what>"; nothing is dropped silently.
//
// Ranges from sensors other than a URG are carried in the scan log as a
// URG-like sensor whose PP block describes their geometry: ARES = steps
// per turn of the beam spacing, AFRT = the step of the 0 rad beam, AMIN /
// AMAX = the first and last beam, DMIN / DMAX the usable ranges in mm.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "stridemap/core/progress.hpp"
#include "stridemap/core/pose_track.hpp"
#include "stridemap/sensors/scip_parameters.hpp"
#include "stridemap/sensors/urg_driver.hpp"

namespace stridemap::io {

/// What an import read, kept and skipped.
struct ImportReport {
  std::size_t lines = 0;    ///< lines read
  std::size_t scans = 0;    ///< scans imported
  std::size_t poses = 0;    ///< poses imported
  std::size_t ignored = 0;  ///< well-formed lines of kinds the importer does not use (comments, CARMEN ODOM...)
  std::size_t skipped = 0;  ///< malformed lines and out_of_order, each with a message in `problems`
  /// Records whose time breaks the increasing order (of `skipped`): those
  /// outside the longest strictly increasing subsequence of the file's times.
  std::size_t out_of_order = 0;
  /// "<file>:<line>: <what>" for the first kMaxImportProblems skipped lines, in line order.
  std::vector<std::string> problems;
};

inline constexpr std::size_t kMaxImportProblems = 1000;

/// Scans and poses ready to be written; `poses` is empty for formats
/// without them.
struct ImportedData {
  std::string format;  ///< "breezyslam", "carmen", "csv-ranges", "tum"
  scip::ScipParameters sensor;
  scip::VersionInfo version;
  std::vector<UrgScan> scans;
  std::vector<TimedPose> poses;
  ImportReport report;
};

/// BreezySLAM logs: token 0 the time [us], tokens 2 and 3 the left and
/// right wheel encoder ticks, tokens 24.. the raw URG-04LX values [mm] with
/// the sensor's error codes. Defaults: the BreezySLAM example rover
/// (its Rover class: WheeledVehicle(77, 165), ticks to degrees as
/// ticks * 180 / 2000).
struct BreezySlamImportOptions {
  double wheel_radius_m = 0.077;
  double half_axle_length_m = 0.165;
  /// Encoder ticks per wheel revolution: 4000, as the example's
  /// ticks * 180 / 2000 degrees.
  double ticks_per_revolution = 4000.0;
  /// Values per scan (the published logs: 683, steps 44..726).
  std::size_t values_per_scan = 683;
  int first_step = 44;
  /// Told the kilobytes of the text read so far.
  ProgressCallback progress{};
};

/// CARMEN logs: FLASER and ROBOTLASER1 lines (ranges in metres and the
/// robot's pose); other messages are ignored. FLASER carries no angles:
/// its beams span `flaser_field_of_view_rad` centred ahead, evenly.
struct CarmenImportOptions {
  double flaser_field_of_view_rad = 3.14159265358979323846;
  /// Shorter ranges are the sensor's "no return" [m].
  double min_range_m = 0.02;
  /// ROBOTLASER1 carries its own maximum range; FLASER uses this [m].
  double flaser_max_range_m = 81.9;
  /// Told the kilobytes of the text read so far.
  ProgressCallback progress{};
};

/// Plain CSV ranges: one scan per line, "time_s, r_0, r_1, ..." (commas,
/// spaces or tabs); '#' lines and a first line that is not numbers (a
/// header) are skipped. Beam k points at angle_min_rad + k angle_step_rad.
struct CsvRangesImportOptions {
  double angle_min_rad = -2.0943951023931953;  ///< -120 deg, the URG-04LX's first beam
  double angle_step_rad = 0.006135923151542565;  ///< 360 / 1024 deg, the URG-04LX's step
  double range_scale_m = 1.0;  ///< metres per unit of the file's ranges (0.001 for millimetres)
  double min_range_m = 0.02;
  double max_range_m = 5.6;
  /// Told the kilobytes of the text read so far.
  ProgressCallback progress{};
};

/// How a point-pair log stores its numbers.
enum class XyEncoding : std::uint8_t {
  int32,    ///< little-endian 32-bit integers, x y x y ...
  float32,  ///< little-endian IEEE 754 single precision
  text,     ///< one scan per line: "x0 y0 x1 y1 ..." (spaces, tabs or commas)
};

/// Point-pair logs: each scan is one (x, y) pair per beam, in beam order,
/// in the sensor's frame (x ahead, y left), with a fixed pair for "no
/// return". The beams' angles are fitted to the points (least squares of
/// atan2(y, x) against the beam number) unless given, and each pair
/// becomes the range of its beam.
struct XyImportOptions {
  XyEncoding encoding = XyEncoding::int32;
  /// Binary: bytes before the first value (a file header).
  std::size_t header_bytes = 0;
  /// Binary: a pair whose x and y both equal this ends a scan.
  std::optional<double> separator;
  /// Binary without a separator: pairs in every scan.
  std::size_t pairs_per_scan = 0;
  double unit_m = 0.001;  ///< metres per unit of x and y (0.001: millimetres)
  double invalid_x = 0.0;  ///< the pair meaning "no return", in the file's units
  double invalid_y = 0.0;
  /// Text: the first number of each line is the scan's time [s].
  bool time_first = false;
  /// Scans without times: scan k is taken at k / scan_rate_hz s.
  std::optional<double> scan_rate_hz;
  /// The beams' angles; both or neither (then fitted to the points).
  std::optional<double> angle_min_rad;
  std::optional<double> angle_step_rad;
  double min_range_m = 0.02;
  double max_range_m = 5.6;
  /// A sensor standing still: this pose at every scan's time.
  std::optional<TrunkPose> static_pose;
  /// Told the kilobytes read so far.
  ProgressCallback progress{};
};

/// What TUM's tz becomes: h_ref (reference_elevation_m), the trunk's
/// height change (height_change_m), each relative to the first pose, or
/// nothing.
enum class TumHeight : std::uint8_t { reference_elevation, height_change, ignore };

struct TumImportOptions {
  TumHeight height = TumHeight::reference_elevation;
  /// Told the kilobytes of the text read so far.
  ProgressCallback progress{};
};

ImportedData import_breezyslam(std::string_view text, const std::string& source,
                               const BreezySlamImportOptions& options = {});
ImportedData import_carmen(std::string_view text, const std::string& source, const CarmenImportOptions& options = {});
ImportedData import_csv_ranges(std::string_view text, const std::string& source,
                               const CsvRangesImportOptions& options = {});
/// `bytes` as XyImportOptions::encoding says. Scans of another pair count
/// than the first are skipped and named; a fit that does not hold (the
/// points not on evenly spaced beams) is an InputError asking for the angles.
ImportedData import_xy(std::string_view bytes, const std::string& source, const XyImportOptions& options);
/// "timestamp tx ty tz qx qy qz qw" per line: poses only. The body frame
/// must be the robot's (X forward, Y left, Z up).
ImportedData import_tum(std::string_view text, const std::string& source, const TumImportOptions& options = {});

/// The largest file read_import_text reads: far beyond any recording the
/// importers are meant for, small enough that a wrong argument (a disk
/// image, a video) is refused before it fills the memory.
inline constexpr std::uint64_t kMaxImportBytes = std::uint64_t{4} << 30;

/// A file to import, read whole after checks that need not read it: a
/// regular file (not a device such as /dev/zero, a pipe or a folder), at
/// most `max_bytes`, text in its first 4 KiB. Throws InputError naming the
/// file and what is wrong.
std::string read_import_text(const std::string& path, std::uint64_t max_bytes = kMaxImportBytes);
/// The same for a file that may be binary (`text_only` false: no text check).
std::string read_import_file(const std::string& path, bool text_only, std::uint64_t max_bytes = kMaxImportBytes);

/// Writes the scan log (only when there are scans) and the pose file (only
/// when there are poses); each appears complete or not at all. Throws
/// InputError naming the file.
void write_imported(const ImportedData& data, const std::string& log_path, const std::string& poses_path,
                    const std::string& source);

}  // namespace stridemap::io
