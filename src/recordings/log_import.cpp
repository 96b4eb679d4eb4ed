#include "stridemap/recordings/log_import.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <new>
#include <numbers>
#include <sstream>

#include "import_lines.hpp"
#include "stridemap/core/error.hpp"
#include "stridemap/io/text_file.hpp"
#include "stridemap/recordings/pose_stream.hpp"
#include "stridemap/recordings/scan_log.hpp"

namespace stridemap::io {
namespace detail {
namespace {

// How far the stored beam angles may lie from the given ones [rad]: far
// below any scanner's angular accuracy (0.1 deg and more), far above what
// printing angles with 6 decimals does (CARMEN writes 0.017453 for 1 deg).
constexpr double kAngleTolerance = 1e-4;

std::string number_text(double value) {
  std::ostringstream text;
  text.precision(10);
  text << value;
  return text.str();
}

}  // namespace

BeamSteps beam_steps(double angle_min_rad, double angle_step_rad, std::size_t count, double min_range_m,
                     double max_range_m, const std::string& source) {
  const auto fail = [&](const std::string& what) { throw InputError(source + ": " + what); };
  if (!(angle_step_rad > 0.0) || !std::isfinite(angle_step_rad) || !std::isfinite(angle_min_rad)) {
    fail("the beams' angle step must be a positive number of radians, got " + number_text(angle_step_rad));
  }
  if (count == 0) fail("a scan without ranges");
  if (!(min_range_m > 0.0) || !(max_range_m > min_range_m) || !std::isfinite(max_range_m)) {
    fail("the range limits must satisfy 0 < min < max, got " + number_text(min_range_m) + " and " +
         number_text(max_range_m) + " m");
  }
  // A beam spacing that puts the first beam between two steps of a turn
  // is carried with `cluster` times finer steps, each value spanning
  // `cluster` of them.
  const double turn_steps = 2.0 * std::numbers::pi / angle_step_rad;
  const double span_rad = static_cast<double>(count - 1) * angle_step_rad;
  int cluster = 1;
  double steps_per_turn = 0.0, first = 0.0;
  for (; cluster <= 16; ++cluster) {
    steps_per_turn = std::round(turn_steps * cluster);
    if (steps_per_turn < 1.0) continue;
    const double fine_step = 2.0 * std::numbers::pi / steps_per_turn;
    first = std::round(angle_min_rad / fine_step);  // relative to the forward step
    const double span_error = std::abs(static_cast<double>(count - 1) * cluster * fine_step - span_rad);
    if (std::abs(first * fine_step - angle_min_rad) < kAngleTolerance && span_error < kAngleTolerance) break;
  }
  if (cluster > 16) {
    fail("beams every " + number_text(angle_step_rad) + " rad from " + number_text(angle_min_rad) +
         " rad do not fall on whole steps of a full turn (2 pi / step = " + number_text(turn_steps) +
         "); give the step as 2 pi divided by a whole number");
  }
  const double last = first + static_cast<double>(count - 1) * cluster;
  if (first > 0.0 || last < 0.0) {
    fail("the beams (" + number_text(angle_min_rad) + " to " +
         number_text(angle_min_rad + static_cast<double>(count - 1) * angle_step_rad) +
         " rad) must include the forward direction, 0 rad");
  }
  if (last - first >= steps_per_turn || steps_per_turn > 1e6) {
    fail("the beams cover more than a full turn (" + std::to_string(count) + " beams every " +
         number_text(angle_step_rad) + " rad)");
  }
  BeamSteps out;
  out.cluster = cluster;
  out.first_step = 0;
  out.sensor.steps_per_turn = static_cast<int>(steps_per_turn);
  out.sensor.first_step = 0;
  out.sensor.front_step = static_cast<int>(-first);
  out.sensor.last_step = static_cast<int>(last - first);
  out.sensor.min_distance_mm = static_cast<int>(std::lround(min_range_m * 1000.0));
  out.sensor.max_distance_mm = static_cast<int>(std::lround(std::min(max_range_m * 1000.0, double{kLargestRawValue})));
  if (out.sensor.max_distance_mm <= out.sensor.min_distance_mm) fail("the range limits are less than 1 mm apart");
  return out;
}

scip::VersionInfo imported_version(const std::string& format) {
  scip::VersionInfo version;
  version.vendor = "unknown (imported by stridemap)";
  version.product = "ranges imported from a " + format + " log";
  version.firmware = "none";
  version.protocol = "none";
  version.serial = "none";
  return version;
}

}  // namespace detail

std::string read_import_text(const std::string& path, std::uint64_t max_bytes) {
  return read_import_file(path, true, max_bytes);
}

std::string read_import_file(const std::string& path, bool text_only, std::uint64_t max_bytes) {
  struct stat info {};
  if (::stat(path.c_str(), &info) != 0) {
    throw InputError(path + ": cannot open the file to import (" + std::strerror(errno) + ")");
  }
  if (S_ISDIR(info.st_mode)) throw InputError(path + ": is a folder, not a file to import");
  // A device or pipe has no size to check and may never end (/dev/zero).
  if (!S_ISREG(info.st_mode)) {
    throw InputError(path + ": not a regular file (a device, pipe or socket); import reads files");
  }
  const auto size = static_cast<std::uint64_t>(info.st_size);
  if (size > max_bytes) {
    throw InputError(path + ": " + std::to_string(size) + " bytes, more than the import limit of " +
                     std::to_string(max_bytes) + " bytes");
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open the file to import (" + std::strerror(errno) + ")");
  // Read into place, once: the size is known, so no growing copy doubles
  // the memory. A file that grows meanwhile is read up to its checked size.
  std::string text;
  try {
    text.resize(static_cast<std::size_t>(size));
  } catch (const std::bad_alloc&) {
    throw InputError(path + ": " + std::to_string(size) + " bytes do not fit in memory; import a smaller part");
  }
  const std::size_t head = std::min<std::size_t>(text.size(), detail::kTextSniffBytes);
  in.read(text.data(), static_cast<std::streamsize>(head));
  std::size_t got = static_cast<std::size_t>(in.gcount());
  if (text_only) detail::text_body(std::string_view(text.data(), got), path);  // binary data refused before the rest is read
  if (got == head && head < text.size()) {
    in.read(text.data() + head, static_cast<std::streamsize>(text.size() - head));
    got += static_cast<std::size_t>(in.gcount());
  }
  if (in.bad()) throw InputError(path + ": cannot read the file to import (" + std::strerror(errno) + ")");
  text.resize(got);
  return text;
}

void write_imported(const ImportedData& data, const std::string& log_path, const std::string& poses_path,
                    const std::string& source) {
  if (!data.scans.empty()) {
    if (log_path.empty()) throw InputError(source + ": the input holds scans; give a scan log to write them to");
    // The writer streams into its file: fill a temporary one beside the
    // destination and rename it once complete.
    const auto slash = log_path.find_last_of('/');
    const std::string folder = slash == std::string::npos ? "" : log_path.substr(0, slash + 1);
    const std::string name = slash == std::string::npos ? log_path : log_path.substr(slash + 1);
    const std::string temp = folder + "." + name + ".import-" + std::to_string(::getpid());
    try {
      {
        ScanLogWriter writer(temp, "imported " + data.format + " " + source);
        writer.write_sensor(data.scans.front().host_time_s, data.version, data.sensor);
        for (const UrgScan& scan : data.scans) writer.write_scan(scan);
        writer.flush();
      }
      if (std::rename(temp.c_str(), log_path.c_str()) != 0) {
        throw InputError(log_path + ": cannot move the finished scan log into place");
      }
    } catch (const InputError& e) {
      std::remove(temp.c_str());
      throw InputError(log_path + ": cannot write the scan log (" + e.what() + ")");
    }
  }
  if (!data.poses.empty()) {
    if (poses_path.empty()) throw InputError(source + ": the input holds poses; give a pose file to write them to");
    std::string text = pose_file_header();
    for (const TimedPose& pose : data.poses) text += format_pose_line(pose) + "\n";
    write_text_file(poses_path, text, "pose file");
  }
}

}  // namespace stridemap::io
