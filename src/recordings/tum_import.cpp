#include <cmath>

#include <Eigen/Geometry>

#include "import_lines.hpp"
#include "stridemap/core/error.hpp"
#include "stridemap/recordings/log_import.hpp"

namespace stridemap::io {

ImportedData import_tum(std::string_view text, const std::string& source, const TumImportOptions& options) {
  ImportedData out;
  out.format = "tum";
  // Kept in file order until every time is known: which times are out of
  // order depends on all of them.
  struct Record {
    std::size_t line = 0;
    double time_s = 0.0;
    double z = 0.0;
    TimedPose pose;
  };
  std::vector<Record> records;
  detail::for_each_line(detail::text_body(text, source), [&](std::string_view line, std::size_t number) {
    ++out.report.lines;
    const auto fields = detail::split_fields(line);
    if (fields.empty() || fields.front().front() == '#') {
      ++out.report.ignored;
      return;
    }
    const auto skip = [&](const std::string& what) { detail::skip_line(out.report, source, number, what); };
    if (fields.size() != 8) {
      return skip(std::to_string(fields.size()) + " fields, expected 8 (timestamp tx ty tz qx qy qz qw)");
    }
    double v[8];
    for (std::size_t k = 0; k < 8; ++k) {
      if (!detail::parse_number(fields[k], v[k])) {
        return skip("field " + std::to_string(k + 1) + " ('" + std::string(fields[k]) + "') is not a finite number");
      }
    }
    Eigen::Quaterniond q(v[7], v[4], v[5], v[6]);
    const double norm = q.norm();
    // Text rounding leaves a quaternion a little off unit length; one far
    // off is not a rotation written with care.
    if (!(std::abs(norm - 1.0) < 0.01)) {
      return skip("the quaternion's length is " + std::to_string(norm) + ", not 1");
    }
    // R = Rz(yaw) Ry(pitch) Rx(roll), the order the mapper composes
    // (core/sensor_transform.hpp); positive pitch about +Y puts the nose down.
    const Eigen::Matrix3d r = q.normalized().toRotationMatrix();
    Record record;
    record.line = number;
    record.time_s = v[0];
    record.z = v[3];
    TimedPose& pose = record.pose;
    pose.time_s = v[0];
    pose.pose.x_m = v[1];
    pose.pose.y_m = v[2];
    pose.pose.yaw_rad = std::atan2(r(1, 0), r(0, 0));
    pose.pose.pitch_rad = std::asin(std::clamp(-r(2, 0), -1.0, 1.0)) + 0.0;  // + 0.0: no "-0" in the file
    pose.pose.roll_rad = std::atan2(r(2, 1), r(2, 2));
    records.push_back(record);
  }, options.progress);
  records = detail::keep_increasing_times(std::move(records), &Record::time_s, out.report, source);
  out.poses.reserve(records.size());
  for (Record& record : records) {
    const double z = record.z - records.front().z;
    if (options.height == TumHeight::reference_elevation) record.pose.pose.reference_elevation_m = z;
    if (options.height == TumHeight::height_change) record.pose.pose.height_change_m = z;
    out.poses.push_back(record.pose);
  }
  out.report.poses = out.poses.size();
  return out;
}

}  // namespace stridemap::io
