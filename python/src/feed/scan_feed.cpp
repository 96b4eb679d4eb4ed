#include "scan_feed.hpp"

#include <cmath>
#include <limits>

#include "stridemap/core/error.hpp"

namespace stridemap::python {
namespace {

// Metres past which a range "in metres" must be millimetres: no URG, nor
// any sensor a walking robot carries, measures 100 m.
constexpr double kImplausibleRangeM = 100.0;

}  // namespace

std::string ArgumentName::text() const {
  std::string name = argument;
  // Appended piece by piece: GCC 12 warns (-Wrestrict, a false positive)
  // about "[" + std::to_string(i) + "]".
  if (row >= 0) {
    name += '[';
    name += std::to_string(row);
    name += ']';
  }
  return name;
}

std::string ArgumentName::element(long long index) const {
  std::string name = text();
  name += '[';
  name += std::to_string(index);
  name += ']';
  return name;
}

double finite_value(double value, const ArgumentName& name) {
  if (!std::isfinite(value)) throw InputError(name.text() + ": expected a finite number, got " + std::to_string(value));
  return value;
}

TrunkPose pose_of_values(const double* v, std::size_t count, double reference_elevation_m, double height_change_m,
                         const ArgumentName& name) {
  static const char* const kFive[] = {"x_m", "y_m", "roll_rad", "pitch_rad", "yaw_rad"};
  static const char* const kSix[] = {"x_m", "y_m", "z_m", "roll_rad", "pitch_rad", "yaw_rad"};
  if (count != 5 && count != 6) {
    throw InputError(name.text() + ": expected 5 values (x_m, y_m, roll_rad, pitch_rad, yaw_rad) or 6 (x_m, y_m, "
                     "z_m, roll_rad, pitch_rad, yaw_rad), got " + std::to_string(count));
  }
  for (std::size_t i = 0; i < count; ++i) {
    if (!std::isfinite(v[i])) {
      throw InputError(name.text() + ": " + (count == 5 ? kFive[i] : kSix[i]) + " is not finite (" +
                       std::to_string(v[i]) + ")");
    }
  }
  TrunkPose pose;
  pose.x_m = v[0];
  pose.y_m = v[1];
  std::size_t k = 2;
  if (count == 6) pose.z_m = v[k++];
  pose.roll_rad = v[k++];
  pose.pitch_rad = v[k++];
  pose.yaw_rad = v[k];
  pose.reference_elevation_m = finite_value(reference_elevation_m, {"reference_elevation_m"});
  pose.height_change_m = finite_value(height_change_m, {"height_change_m"});
  return pose;
}

RangeUnits range_units(const std::string& units) {
  if (units == "mm") return RangeUnits::mm;
  if (units == "m") return RangeUnits::m;
  throw InputError("units: expected 'mm' (raw URG values) or 'm', got '" + units + "'");
}

ScanFeed::ScanFeed(MappingPipeline& pipeline)
    : pipeline_(pipeline), urg_(pipeline.options().urg, pipeline.options().calibration) {}

// The raw scan the URG would have sent: millimetres as given (units "mm",
// integers: error codes below DMIN kept), or metres rounded to millimetres
// (units "m", floats: NaN / inf / 0 become code 0, "no echo").
void ScanFeed::fill_raw(const double* values, std::size_t count, RangeUnits units, double time_s, int first_step,
                        int cluster, const ArgumentName& ranges) {
  raw_.time_s = time_s;
  raw_.first_step = first_step;
  raw_.cluster = cluster;
  raw_.values_mm.resize(count);
  for (std::size_t i = 0; i < count; ++i) {
    const double v = values[i];
    const auto at = [&] { return ranges.element(static_cast<long long>(i)); };
    if (units == RangeUnits::mm) {
      if (v < 0.0 || v > static_cast<double>(std::numeric_limits<std::uint32_t>::max())) {
        throw InputError(at() + ": a raw URG value is 0..4294967295 mm, got " +
                         std::to_string(static_cast<long long>(v)));
      }
      raw_.values_mm[i] = static_cast<std::uint32_t>(v);
    } else if (!std::isfinite(v) || v == 0.0) {
      raw_.values_mm[i] = 0;
    } else if (v < 0.0) {
      throw InputError(at() + ": a range is not negative, got " + std::to_string(v) + " m");
    } else if (v > kImplausibleRangeM) {
      throw InputError(at() + ": " + std::to_string(v) + " m is no range a URG measures; are these millimetres "
                       "(units='mm')?");
    } else {
      raw_.values_mm[i] = static_cast<std::uint32_t>(std::lround(v * 1000.0));
    }
  }
  // The pipeline counts a scan that does not fit the sensor as rejected
  // and goes on (a live stream must); a script wants to hear why.
  urg_.check_fits(raw_);
}

ScanOutcome ScanFeed::add_urg(const double* values, std::size_t count, RangeUnits units, double time_s,
                              std::optional<int> first_step, int cluster, const TrunkPose& pose) {
  fill_raw(values, count, units, time_s, first_step.value_or(pipeline_.options().urg.first_step), cluster, {"ranges"});
  return pipeline_.add(raw_, pose);
}

UrgBatchCounts ScanFeed::add_urg_batch(const UrgBatch& b) {
  const PipelineStats stats_before = pipeline_.stats();
  const MapperTotals totals_before = pipeline_.mapper().totals();
  UrgBatchCounts counts;
  for (std::size_t i = 0; i < b.scans; ++i) {
    const auto row = static_cast<long long>(i);
    const TrunkPose pose = pose_of_values(b.poses + i * b.pose_values, b.pose_values,
                                          b.reference_elevation_m ? b.reference_elevation_m[i] : 0.0,
                                          b.height_change_m ? b.height_change_m[i] : 0.0, {"poses", row});
    const double time_s = finite_value(b.times_s[i], {"times_s", row});
    fill_raw(b.ranges + i * b.values_per_scan, b.values_per_scan, b.units, time_s, pipeline_.options().urg.first_step,
             1, {"ranges", row});
    const ScanOutcome outcome = pipeline_.add(raw_, pose);
    if (outcome.stats.time_rejected && !counts.first_stale) counts.first_stale = i;
  }
  const PipelineStats stats = pipeline_.stats();
  const MapperTotals& totals = pipeline_.mapper().totals();
  counts.stale = totals.scans_rejected_for_time - totals_before.scans_rejected_for_time;
  counts.bad_pose = totals.scans_rejected_for_pose - totals_before.scans_rejected_for_pose;
  counts.unfit = stats.rejected - stats_before.rejected;
  counts.mapped = stats.integrated - stats_before.integrated - counts.stale - counts.bad_pose;
  return counts;
}

ScanOutcome ScanFeed::add_points(const double* xyz, std::size_t count, const double* sigma_m, bool one_sigma,
                                 double time_s, const TrunkPose& pose) {
  points_.time_s = time_s;
  points_.points_m.resize(count);
  points_.height_sigma_m.resize(count);
  for (std::size_t i = 0; i < count; ++i) {
    points_.points_m[i] = {xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]};
    points_.height_sigma_m[i] = one_sigma ? sigma_m[0] : sigma_m[i];
  }
  return pipeline_.add(points_, pose);
}

ScanOutcome ScanFeed::add_stripe(const double* uv, std::size_t count, std::optional<double> time_s,
                                 const TrunkPose& pose) {
  stripe_.resize(count);
  for (std::size_t i = 0; i < count; ++i) stripe_[i] = {uv[2 * i], uv[2 * i + 1]};
  return pipeline_.add(stripe_, time_s, pose);
}

}  // namespace stridemap::python
