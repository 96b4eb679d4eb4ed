#include "stridemap/sensors/scip_parameters.hpp"

#include <charconv>
#include <cstdio>
#include <string>

#include "stridemap/core/error.hpp"

namespace stridemap::scip {

namespace {

const std::string& require_field(const std::vector<InfoField>& fields, std::string_view key,
                                 std::string_view reply) {
  const std::string* value = find_field(fields, key);
  if (value == nullptr) {
    throw InputError("SCIP " + std::string(reply) + " reply: field " + std::string(key) + " is missing");
  }
  return *value;
}

int require_integer(const std::vector<InfoField>& fields, std::string_view key) {
  const std::string& text = require_field(fields, key, "PP");
  // from_chars reports overflow instead of wrapping; a sign is not allowed.
  int value = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  const bool ok = !text.empty() && text.front() != '-' && error == std::errc() && end == text.data() + text.size();
  if (!ok) {
    throw InputError("SCIP PP reply: field " + std::string(key) + " value '" + text +
                     "' is not a non-negative decimal integer");
  }
  return value;
}

[[noreturn]] void inconsistent(std::string_view key, int value, std::string_view why) {
  throw InputError("SCIP PP reply: field " + std::string(key) + " = " + std::to_string(value) + " " +
                   std::string(why));
}

}  // namespace

ScipParameters parse_parameters(const std::vector<InfoField>& fields) {
  ScipParameters parameters;
  parameters.model = require_field(fields, "MODL", "PP");
  parameters.min_distance_mm = require_integer(fields, "DMIN");
  parameters.max_distance_mm = require_integer(fields, "DMAX");
  parameters.steps_per_turn = require_integer(fields, "ARES");
  parameters.first_step = require_integer(fields, "AMIN");
  parameters.last_step = require_integer(fields, "AMAX");
  parameters.front_step = require_integer(fields, "AFRT");
  parameters.motor_speed_rpm = require_integer(fields, "SCAN");
  return parameters;
}

VersionInfo parse_version(const std::vector<InfoField>& fields) {
  VersionInfo version;
  version.vendor = require_field(fields, "VEND", "VV");
  version.product = require_field(fields, "PROD", "VV");
  version.firmware = require_field(fields, "FIRM", "VV");
  version.protocol = require_field(fields, "PROT", "VV");
  version.serial = require_field(fields, "SERI", "VV");
  return version;
}

StatusInfo parse_status_info(const std::vector<InfoField>& fields) {
  StatusInfo status;
  status.model = require_field(fields, "MODL", "II");
  const std::string& laser = require_field(fields, "LASR", "II");
  if (laser != "ON" && laser != "OFF") {
    throw InputError("SCIP II reply: field LASR value '" + laser + "' is neither ON nor OFF");
  }
  status.laser_on = laser == "ON";
  status.motor_speed = require_field(fields, "SCSP", "II");
  status.measurement_mode = require_field(fields, "MESM", "II");
  status.bit_rate = require_field(fields, "SBPS", "II");
  const std::string& time = require_field(fields, "TIME", "II");
  std::uint32_t time_ms = 0;
  const auto [end, error] = std::from_chars(time.data(), time.data() + time.size(), time_ms, 16);
  if (time.empty() || time.size() > 6 || error != std::errc() || end != time.data() + time.size()) {
    throw InputError("SCIP II reply: field TIME value '" + time + "' is not 1-6 hexadecimal digits");
  }
  status.time_ms = time_ms;
  status.state = require_field(fields, "STAT", "II");
  return status;
}

UrgParameters to_urg_parameters(const ScipParameters& p) {
  if (p.steps_per_turn <= 0) inconsistent("ARES", p.steps_per_turn, "must be positive");
  if (p.motor_speed_rpm <= 0) inconsistent("SCAN", p.motor_speed_rpm, "must be positive");
  if (p.first_step < 0) inconsistent("AMIN", p.first_step, "must not be negative");
  if (p.last_step < p.first_step) {
    inconsistent("AMAX", p.last_step, "is below AMIN = " + std::to_string(p.first_step));
  }
  if (p.last_step >= p.steps_per_turn) {
    inconsistent("AMAX", p.last_step, "is not below ARES = " + std::to_string(p.steps_per_turn));
  }
  // GD/MD name steps in four digits: a larger AMAX is no URG's.
  if (p.last_step > 9999) inconsistent("AMAX", p.last_step, "is above 9999, the largest step a scan command can name");
  if (p.front_step < 0 || p.front_step >= p.steps_per_turn) {
    inconsistent("AFRT", p.front_step, "is outside 0..ARES-1 = " + std::to_string(p.steps_per_turn - 1));
  }
  if (p.min_distance_mm < 0) inconsistent("DMIN", p.min_distance_mm, "must not be negative");
  if (p.max_distance_mm <= p.min_distance_mm) {
    inconsistent("DMAX", p.max_distance_mm, "is not above DMIN = " + std::to_string(p.min_distance_mm));
  }
  UrgParameters urg;
  urg.first_step = p.first_step;
  urg.last_step = p.last_step;
  urg.front_step = p.front_step;
  urg.steps_per_turn = p.steps_per_turn;
  urg.min_range_m = p.min_distance_mm * 1e-3;
  urg.max_range_m = p.max_distance_mm * 1e-3;
  urg.scan_period_s = 60.0 / p.motor_speed_rpm;
  return urg;
}

std::vector<InfoField> to_info_fields(const ScipParameters& p) {
  return {{"MODL", p.model},
          {"DMIN", std::to_string(p.min_distance_mm)},
          {"DMAX", std::to_string(p.max_distance_mm)},
          {"ARES", std::to_string(p.steps_per_turn)},
          {"AMIN", std::to_string(p.first_step)},
          {"AMAX", std::to_string(p.last_step)},
          {"AFRT", std::to_string(p.front_step)},
          {"SCAN", std::to_string(p.motor_speed_rpm)}};
}

std::vector<InfoField> to_info_fields(const VersionInfo& v) {
  return {{"VEND", v.vendor}, {"PROD", v.product}, {"FIRM", v.firmware}, {"PROT", v.protocol}, {"SERI", v.serial}};
}

std::vector<InfoField> to_info_fields(const StatusInfo& s) {
  char time[8];
  std::snprintf(time, sizeof time, "%06X", static_cast<unsigned>(s.time_ms & 0xFFFFFFu));
  return {{"MODL", s.model},         {"LASR", s.laser_on ? "ON" : "OFF"}, {"SCSP", s.motor_speed},
          {"MESM", s.measurement_mode}, {"SBPS", s.bit_rate},             {"TIME", time},
          {"STAT", s.state}};
}

}  // namespace stridemap::scip
