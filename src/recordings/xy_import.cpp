// Point-pair logs (import_xy): scans stored as the (x, y) of each beam's
// return rather than as ranges, as many robot logs keep them. The beam
// angles are not in the file; they are fitted to the points, so that the
// scan log carries ranges on the sensor's own evenly spaced beams.
#include <bit>
#include <cmath>
#include <cstring>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "import_lines.hpp"
#include "stridemap/core/error.hpp"
#include "stridemap/recordings/log_import.hpp"

namespace stridemap::io {
namespace {

constexpr double kDegPerRad = 180.0 / std::numbers::pi;
// Scans the angle fit reads: plenty for a steady fit, bounded for long logs.
constexpr std::size_t kFitScans = 200;

struct PairScan {
  std::size_t line = 0;  // text: its line; binary: the byte offset of its first pair
  double time_s = 0.0;
  std::vector<double> xy;  // x0 y0 x1 y1 ... in the file's units
};

void skip_binary(ImportReport& report, const std::string& source, std::size_t offset, const std::string& what) {
  ++report.skipped;
  if (report.problems.size() < kMaxImportProblems) {
    report.problems.push_back(source + ": byte " + std::to_string(offset) + ": " + what);
  }
}

double binary_value(const char* at, XyEncoding encoding) {
  std::uint32_t bits = 0;
  std::memcpy(&bits, at, sizeof bits);
  if constexpr (std::endian::native == std::endian::big) bits = __builtin_bswap32(bits);
  if (encoding == XyEncoding::int32) return static_cast<double>(std::bit_cast<std::int32_t>(bits));
  return static_cast<double>(std::bit_cast<float>(bits));
}

std::vector<PairScan> read_binary(std::string_view bytes, const std::string& source, const XyImportOptions& o,
                                  ImportReport& report) {
  if (!o.separator && o.pairs_per_scan == 0) {
    throw InputError(source + ": binary point pairs need a way to tell the scans apart: a separator value "
                              "(--separator) or the pairs in every scan (--pairs-per-scan)");
  }
  if (o.header_bytes > bytes.size()) {
    throw InputError(source + ": the header of " + std::to_string(o.header_bytes) + " bytes is longer than the file (" +
                     std::to_string(bytes.size()) + " bytes)");
  }
  const std::size_t end = o.header_bytes + (bytes.size() - o.header_bytes) / 8 * 8;
  if (end != bytes.size()) {
    skip_binary(report, source, end, std::to_string(bytes.size() - end) + " bytes at the end are not a whole pair");
  }
  std::vector<PairScan> scans;
  PairScan scan;
  scan.line = o.header_bytes;
  const auto close = [&](std::size_t next) {
    if (!scan.xy.empty()) scans.push_back(std::move(scan));
    scan = PairScan{};
    scan.line = next;
  };
  for (std::size_t at = o.header_bytes; at < end; at += 8) {
    const double x = binary_value(bytes.data() + at, o.encoding), y = binary_value(bytes.data() + at + 4, o.encoding);
    if (o.separator && x == *o.separator && y == *o.separator) {
      close(at + 8);
      continue;
    }
    scan.xy.push_back(x);
    scan.xy.push_back(y);
    if (!o.separator && scan.xy.size() == 2 * o.pairs_per_scan) close(at + 8);
    if (o.progress && (at - o.header_bytes) % (1u << 20) == 0) o.progress(at / 1024, bytes.size() / 1024);
  }
  if (!o.separator && !scan.xy.empty()) {
    skip_binary(report, source, scan.line,
                "the last scan has " + std::to_string(scan.xy.size() / 2) + " of " + std::to_string(o.pairs_per_scan) +
                    " pairs (cut short)");
  } else {
    close(end);
  }
  if (o.progress) o.progress(bytes.size() / 1024, bytes.size() / 1024);
  report.lines = scans.size();
  return scans;
}

std::vector<PairScan> read_text(std::string_view bytes, const std::string& source, const XyImportOptions& o,
                                ImportReport& report) {
  std::vector<PairScan> scans;
  detail::for_each_line(detail::text_body(bytes, source), [&](std::string_view line, std::size_t number) {
    ++report.lines;
    const auto fields = detail::split_fields(line, true);
    if (fields.empty() || fields.front().front() == '#') {
      ++report.ignored;
      return;
    }
    PairScan scan;
    scan.line = number;
    std::size_t first = 0;
    if (o.time_first) {
      if (!detail::parse_number(fields[0], scan.time_s)) {
        return detail::skip_line(report, source, number, "time '" + std::string(fields[0]) + "' is not a number");
      }
      first = 1;
    }
    if ((fields.size() - first) % 2 != 0 || fields.size() == first) {
      return detail::skip_line(report, source, number,
                               std::to_string(fields.size() - first) + " values, not a whole number of (x, y) pairs");
    }
    for (std::size_t k = first; k < fields.size(); ++k) {
      double v = 0.0;
      if (!detail::parse_number(fields[k], v)) {
        if (!scans.empty() || number > 1 || k > first) {
          return detail::skip_line(report, source, number,
                                   "value " + std::to_string(k + 1) + " ('" + std::string(fields[k]) + "') is not a number");
        }
        ++report.ignored;  // a header line naming the columns
        return;
      }
      scan.xy.push_back(v);
    }
    scans.push_back(std::move(scan));
  }, o.progress);
  return scans;
}

bool no_return(double x, double y, const XyImportOptions& o) {
  return !std::isfinite(x) || !std::isfinite(y) || (x == o.invalid_x && y == o.invalid_y);
}

struct BeamAngles {
  double min_rad = 0.0;
  double step_rad = 0.0;
};

// Least squares of each return's bearing against its beam number. A
// scanner's steps divide the turn evenly (1024 for the URG-04LX), so a fit
// within a quarter step of such a spacing is snapped to it.
BeamAngles fit_beam_angles(const std::vector<PairScan>& scans, std::size_t beams, const std::string& source,
                           const XyImportOptions& o) {
  Eigen::Matrix2d normal = Eigen::Matrix2d::Zero();
  Eigen::Vector2d rhs = Eigen::Vector2d::Zero();
  std::vector<std::pair<double, double>> samples;  // (beam, bearing)
  for (std::size_t s = 0; s < scans.size() && s < kFitScans; ++s) {
    for (std::size_t k = 0; k < beams; ++k) {
      const double x = scans[s].xy[2 * k], y = scans[s].xy[2 * k + 1];
      if (no_return(x, y, o)) continue;
      const Eigen::Vector2d row(1.0, static_cast<double>(k));
      const double bearing = std::atan2(y, x);
      normal += row * row.transpose();
      rhs += row * bearing;
      samples.emplace_back(static_cast<double>(k), bearing);
    }
  }
  const auto ask = [&](const std::string& why) {
    throw InputError(source + ": " + why + "; give the beams' angles with --angle-min-deg and --angle-step-deg");
  };
  if (samples.size() < 2 || normal.determinant() <= 1e-9 * normal.trace()) {
    ask("fewer than two beams with a return, so their angles cannot be fitted");
  }
  const Eigen::Vector2d fit = normal.ldlt().solve(rhs);
  double squares = 0.0;
  for (const auto& [k, bearing] : samples) squares += std::pow(bearing - fit(0) - fit(1) * k, 2);
  const double rms_rad = std::sqrt(squares / static_cast<double>(samples.size()));
  const std::string fitted = "first beam " + detail::time_text(fit(0) * kDegPerRad) + " deg, step " +
                             detail::time_text(fit(1) * kDegPerRad) + " deg, RMS off the fit " +
                             detail::time_text(rms_rad * kDegPerRad) + " deg";
  if (!(fit(1) > 0.0)) ask("the beams do not turn counter-clockwise in file order (" + fitted + ")");
  if (!(rms_rad < 0.25 * fit(1))) ask("the points do not lie on evenly spaced beams (" + fitted + ")");
  BeamAngles angles{fit(0), fit(1)};
  const double steps_per_turn = std::round(2.0 * std::numbers::pi / fit(1));
  const double even_step = 2.0 * std::numbers::pi / steps_per_turn;
  // Within 1 mrad over the whole fan: far below the scanners' angular accuracy.
  if (std::abs(even_step - fit(1)) * static_cast<double>(beams) < 1e-3) {
    angles.step_rad = even_step;
    const double first = std::round(fit(0) / even_step) * even_step;
    if (std::abs(first - fit(0)) < 1e-3) angles.min_rad = first;
  }
  return angles;
}

}  // namespace

ImportedData import_xy(std::string_view bytes, const std::string& source, const XyImportOptions& o) {
  if (!(o.unit_m > 0.0) || !std::isfinite(o.unit_m)) {
    throw InputError(source + ": point pairs import: the unit must be a positive number of metres");
  }
  if (o.angle_min_rad.has_value() != o.angle_step_rad.has_value()) {
    throw InputError(source + ": give both beam angles (--angle-min-deg and --angle-step-deg) or neither");
  }
  const bool file_times = o.encoding == XyEncoding::text && o.time_first;
  if (file_times && o.scan_rate_hz) {
    throw InputError(source + ": the scans' times come from the file (--time-first); leave out --scan-rate-hz");
  }
  if (!file_times && !o.scan_rate_hz) {
    throw InputError(source + ": the scans carry no times; give the sensor's scan rate (--scan-rate-hz, 10 for a "
                              "URG-04LX)" + std::string(o.encoding == XyEncoding::text ? " or --time-first" : ""));
  }
  if (o.scan_rate_hz && !(*o.scan_rate_hz > 0.0 && *o.scan_rate_hz <= 10000.0)) {
    throw InputError(source + ": --scan-rate-hz: expected a rate from 0 to 10000 Hz, got " +
                     detail::time_text(*o.scan_rate_hz));
  }
  ImportedData out;
  out.format = "xy";
  out.version = detail::imported_version("XY point pairs");
  std::vector<PairScan> scans =
      o.encoding == XyEncoding::text ? read_text(bytes, source, o, out.report) : read_binary(bytes, source, o, out.report);
  if (scans.empty()) return out;
  const std::size_t beams = scans.front().xy.size() / 2;
  std::erase_if(scans, [&](const PairScan& scan) {
    if (scan.xy.size() / 2 == beams) return false;
    const std::string what = std::to_string(scan.xy.size() / 2) + " pairs, the first scan had " + std::to_string(beams);
    if (o.encoding == XyEncoding::text) {
      detail::skip_line(out.report, source, scan.line, what);
    } else {
      skip_binary(out.report, source, scan.line, what);
    }
    return true;
  });
  for (std::size_t k = 0; k < scans.size() && !file_times; ++k) {
    scans[k].time_s = static_cast<double>(k) / *o.scan_rate_hz;
  }
  if (file_times) scans = detail::keep_increasing_times(std::move(scans), &PairScan::time_s, out.report, source);
  const BeamAngles angles = o.angle_min_rad ? BeamAngles{*o.angle_min_rad, *o.angle_step_rad}
                                            : fit_beam_angles(scans, beams, source, o);
  detail::BeamSteps layout;
  try {
    layout = detail::beam_steps(angles.min_rad, angles.step_rad, beams, o.min_range_m, o.max_range_m, source);
  } catch (const InputError& e) {
    if (o.angle_min_rad) throw;
    throw InputError(std::string(e.what()) + " (angles fitted to the points; give --angle-min-deg and --angle-step-deg)");
  }
  out.sensor = layout.sensor;
  out.sensor.model = "XY point pairs (imported)";
  out.scans.reserve(scans.size());
  for (const PairScan& scan : scans) {
    std::vector<std::uint32_t> values(beams, 0);  // 0: no return
    for (std::size_t k = 0; k < beams; ++k) {
      const double x = scan.xy[2 * k], y = scan.xy[2 * k + 1];
      if (no_return(x, y, o)) continue;
      values[k] = detail::limited_range_to_raw_mm(std::hypot(x, y) * o.unit_m, o.max_range_m, out.sensor.max_distance_mm);
    }
    out.scans.push_back(detail::make_scan(out.scans.size(), scan.time_s, scans.front().time_s, layout.first_step,
                                          layout.cluster, std::move(values)));
    if (o.static_pose) out.poses.push_back(TimedPose{scan.time_s, *o.static_pose});
  }
  out.report.scans = out.scans.size();
  out.report.poses = out.poses.size();
  return out;
}

}  // namespace stridemap::io
