#include <cmath>
#include <optional>

#include "import_lines.hpp"
#include "stridemap/core/error.hpp"
#include "stridemap/recordings/log_import.hpp"

namespace stridemap::io {
namespace {

// One laser message, whichever line it came from.
struct LaserLine {
  double angle_min_rad = 0.0;
  double angle_step_rad = 0.0;
  double max_range_m = 0.0;
  std::vector<double> ranges_m;
  double x_m = 0.0, y_m = 0.0, theta_rad = 0.0;  // the robot's pose
  double time_s = 0.0;
};

// Reads numbers from fields[at..] in order; false at the first that is missing or not a number.
class NumberCursor {
 public:
  NumberCursor(const std::vector<std::string_view>& fields, std::size_t at) : fields_(fields), at_(at) {}
  template <typename T>
  bool next(T& out) {
    return at_ < fields_.size() && detail::parse_number(fields_[at_++], out);
  }
  std::size_t position() const { return at_; }
  std::size_t left() const { return at_ < fields_.size() ? fields_.size() - at_ : 0; }
  void skip(std::size_t count) { at_ += count; }

 private:
  const std::vector<std::string_view>& fields_;
  std::size_t at_;
};

constexpr std::size_t kMaxReadings = 10000;  // far more than any scanner

// FLASER n r_1..r_n x y theta odom_x odom_y odom_theta ipc_timestamp host logger_timestamp
std::optional<std::string> read_flaser(const std::vector<std::string_view>& f, const CarmenImportOptions& options,
                                       LaserLine& out) {
  NumberCursor c(f, 1);
  std::size_t n = 0;
  if (!c.next(n) || n == 0 || n > kMaxReadings) return "FLASER: expected the number of readings (1.." + std::to_string(kMaxReadings) + ")";
  if (f.size() != n + 11) {
    return "FLASER with " + std::to_string(n) + " readings has " + std::to_string(f.size()) + " fields, expected " +
           std::to_string(n + 11);
  }
  out.ranges_m.resize(n);
  for (double& r : out.ranges_m) {
    if (!c.next(r)) return "FLASER: reading " + std::to_string(c.position() - 2) + " is not a number";
  }
  double odom[3];
  if (!c.next(out.x_m) || !c.next(out.y_m) || !c.next(out.theta_rad) || !c.next(odom[0]) || !c.next(odom[1]) ||
      !c.next(odom[2])) {
    return "FLASER: pose or odometry is not a number";
  }
  if (!c.next(out.time_s)) return "FLASER: the timestamp '" + std::string(f[c.position() - 1]) + "' is not a finite number";
  // Evenly over the field of view: 181 readings of a 180 deg scanner are 1 deg apart.
  out.angle_step_rad = n > 1 ? options.flaser_field_of_view_rad / static_cast<double>(n - 1) : 1.0;
  out.angle_min_rad = n > 1 ? -0.5 * options.flaser_field_of_view_rad : 0.0;
  out.max_range_m = options.flaser_max_range_m;
  return std::nullopt;
}

// ROBOTLASER1 type start fov resolution max_range accuracy remission_mode n r_1..r_n m e_1..e_m
//   laser_x laser_y laser_theta robot_x robot_y robot_theta tv rv forward_safety side_safety turn_axis
//   timestamp host logger_timestamp
std::optional<std::string> read_robotlaser(const std::vector<std::string_view>& f, LaserLine& out) {
  NumberCursor c(f, 1);
  double type = 0, fov = 0, accuracy = 0, remission_mode = 0;
  std::size_t n = 0, m = 0;
  if (!c.next(type) || !c.next(out.angle_min_rad) || !c.next(fov) || !c.next(out.angle_step_rad) ||
      !c.next(out.max_range_m) || !c.next(accuracy) || !c.next(remission_mode)) {
    return "ROBOTLASER1: the laser's type, angles, maximum range, accuracy or remission mode is not a number";
  }
  if (!c.next(n) || n == 0 || n > kMaxReadings) return "ROBOTLASER1: expected the number of readings (1.." + std::to_string(kMaxReadings) + ")";
  out.ranges_m.resize(n);
  for (double& r : out.ranges_m) {
    if (!c.next(r)) return "ROBOTLASER1: reading " + std::to_string(c.position() - 9) + " is missing or not a number";
  }
  if (!c.next(m) || m > kMaxReadings) return "ROBOTLASER1: expected the number of remission values";
  if (c.left() != m + 14) {
    return "ROBOTLASER1 with " + std::to_string(n) + " readings and " + std::to_string(m) + " remissions has " +
           std::to_string(f.size()) + " fields, expected " + std::to_string(10 + n + m + 14);
  }
  c.skip(m + 3);  // remissions, the laser's pose
  double ignored = 0;
  if (!c.next(out.x_m) || !c.next(out.y_m) || !c.next(out.theta_rad)) return "ROBOTLASER1: the robot's pose is not a number";
  for (int k = 0; k < 5; ++k) {
    if (!c.next(ignored)) return "ROBOTLASER1: velocities or safety distances are not numbers";
  }
  if (!c.next(out.time_s)) {
    return "ROBOTLASER1: the timestamp '" + std::string(f[c.position() - 1]) + "' is not a finite number";
  }
  return std::nullopt;
}

}  // namespace

ImportedData import_carmen(std::string_view text, const std::string& source, const CarmenImportOptions& options) {
  if (!(options.flaser_field_of_view_rad > 0.0) || !(options.min_range_m > 0.0) ||
      !(options.flaser_max_range_m > options.min_range_m)) {
    throw InputError(source + ": CARMEN import: the field of view and range limits must be positive, max > min");
  }
  ImportedData out;
  out.format = "carmen";
  out.version = detail::imported_version("CARMEN");
  std::optional<detail::BeamSteps> layout;
  LaserLine first_geometry;
  // Kept in file order until every time is known: which times are out of
  // order depends on all of them.
  struct Record {
    std::size_t line = 0;
    double time_s = 0.0;
    std::vector<std::uint32_t> values;
    TimedPose pose;
  };
  std::vector<Record> records;
  detail::for_each_line(detail::text_body(text, source), [&](std::string_view line, std::size_t number) {
    ++out.report.lines;
    const auto fields = detail::split_fields(line);
    const std::string_view kind = fields.empty() ? std::string_view{} : fields.front();
    if (kind != "FLASER" && kind != "ROBOTLASER1") {
      ++out.report.ignored;  // comments, PARAM, ODOM, other sensors: not what the map needs
      return;
    }
    LaserLine laser;
    const auto problem = kind == "FLASER" ? read_flaser(fields, options, laser) : read_robotlaser(fields, laser);
    if (problem) return detail::skip_line(out.report, source, number, *problem);
    if (!layout) {
      try {
        layout = detail::beam_steps(laser.angle_min_rad, laser.angle_step_rad, laser.ranges_m.size(),
                                    options.min_range_m, laser.max_range_m, source + ":" + std::to_string(number));
      } catch (const InputError& e) {
        return detail::skip_line(out.report, source, number, e.what());
      }
      out.sensor = layout->sensor;
      out.sensor.model = "CARMEN laser (imported)";
      first_geometry = laser;
    } else if (laser.ranges_m.size() != first_geometry.ranges_m.size() ||
               std::abs(laser.angle_min_rad - first_geometry.angle_min_rad) > 1e-4 ||
               std::abs(laser.angle_step_rad - first_geometry.angle_step_rad) *
                       static_cast<double>(laser.ranges_m.size()) > 1e-4) {
      return detail::skip_line(out.report, source, number,
                               "the laser's geometry differs from the first scan's (another laser?): " +
                                   std::to_string(laser.ranges_m.size()) + " readings against " +
                                   std::to_string(first_geometry.ranges_m.size()));
    }
    Record record;
    record.line = number;
    record.time_s = laser.time_s;
    record.values.resize(laser.ranges_m.size());
    for (std::size_t k = 0; k < record.values.size(); ++k) {
      record.values[k] =
          detail::limited_range_to_raw_mm(laser.ranges_m[k], laser.max_range_m, out.sensor.max_distance_mm);
    }
    record.pose.time_s = laser.time_s;
    record.pose.pose.x_m = laser.x_m;
    record.pose.pose.y_m = laser.y_m;
    record.pose.pose.yaw_rad = laser.theta_rad;
    records.push_back(std::move(record));
  }, options.progress);
  records = detail::keep_increasing_times(std::move(records), &Record::time_s, out.report, source);
  out.scans.reserve(records.size());
  out.poses.reserve(records.size());
  for (Record& record : records) {
    out.scans.push_back(detail::make_scan(out.scans.size(), record.time_s, records.front().time_s,
                                          layout->first_step, layout->cluster, std::move(record.values)));
    out.poses.push_back(record.pose);
  }
  out.report.scans = out.scans.size();
  out.report.poses = out.poses.size();
  return out;
}

}  // namespace stridemap::io
