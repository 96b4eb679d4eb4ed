#pragma once
// The sensor's own description of itself: the PP reply (model, distance
// limits, step range, front step, resolution, motor speed) and the VV reply
// (vendor, product, firmware, protocol, serial number) and the II reply
// (laser, motor, mode, bit rate, time, state), parsed from the
// decoder's KEY:value fields, converted to the sensor model's UrgParameters,
// and turned back into fields for an emulator's replies.
#include <cstdint>
#include <string>
#include <vector>

#include "stridemap/sensors/scip_reply.hpp"
#include "stridemap/sensors/urg04lx.hpp"

namespace stridemap::scip {

/// PP reply. Defaults are a URG-04LX (spec Table 2).
struct ScipParameters {
  std::string model = "URG-04LX(Hokuyo Automatic Co.,Ltd.)";  ///< MODL
  int min_distance_mm = 20;    ///< DMIN: smaller values are error codes
  int max_distance_mm = 5600;  ///< DMAX
  int steps_per_turn = 1024;   ///< ARES: angular resolution, steps per 360 degrees
  int first_step = 44;         ///< AMIN: first measurable step
  int last_step = 725;         ///< AMAX: last measurable step
  int front_step = 384;        ///< AFRT: step pointing straight ahead
  int motor_speed_rpm = 600;   ///< SCAN: standard motor speed

  bool operator==(const ScipParameters&) const = default;
};

/// VV reply.
struct VersionInfo {
  std::string vendor;    ///< VEND
  std::string product;   ///< PROD
  std::string firmware;  ///< FIRM
  std::string protocol;  ///< PROT, "SCIP 2.0"
  std::string serial;    ///< SERI

  bool operator==(const VersionInfo&) const = default;
};

/// II reply: the sensor's state. Defaults are what a URG-04LX reports idle.
struct StatusInfo {
  std::string model = "URG-04LX(Hokuyo Automatic Co.,Ltd.)";  ///< MODL
  bool laser_on = false;                ///< LASR: "ON" / "OFF"
  std::string motor_speed = "Stable 600[rpm]";  ///< SCSP, free text
  std::string measurement_mode = "IDLE";         ///< MESM, free text ("IDLE", "Measuring"...)
  std::string bit_rate = "115200";               ///< SBPS, free text
  std::uint32_t time_ms = 0;            ///< TIME: the 24-bit millisecond counter, sent as 6 hex digits
  std::string state = "Sensor works well.";  ///< STAT, free text

  bool operator==(const StatusInfo&) const = default;
};

/// Reads MODL, DMIN, DMAX, ARES, AMIN, AMAX, AFRT and SCAN (other keys are
/// ignored). Throws InputError naming the field when one is missing or not a
/// non-negative decimal integer.
ScipParameters parse_parameters(const std::vector<InfoField>& fields);

/// Reads VEND, PROD, FIRM, PROT and SERI; throws InputError naming a missing field.
VersionInfo parse_version(const std::vector<InfoField>& fields);

/// Reads MODL, LASR, SCSP, MESM, SBPS, TIME and STAT; throws InputError
/// naming a missing field, a LASR other than ON/OFF, or a TIME that is not
/// 1-6 hexadecimal digits.
StatusInfo parse_status_info(const std::vector<InfoField>& fields);

/// Geometry and limits for the sensor model: steps AMIN..AMAX, front AFRT,
/// ARES steps per turn, DMIN/DMAX in metres, scan period 60 / SCAN seconds.
/// Throws InputError naming the PP field when the set is inconsistent
/// (ARES or SCAN not positive, AMIN > AMAX, AMAX or AFRT outside the turn,
/// DMIN >= DMAX).
UrgParameters to_urg_parameters(const ScipParameters& parameters);

/// Fields in the order a URG-04LX sends them (MODL DMIN DMAX ARES AMIN AMAX AFRT SCAN).
std::vector<InfoField> to_info_fields(const ScipParameters& parameters);
/// Fields in the order VEND PROD FIRM PROT SERI.
std::vector<InfoField> to_info_fields(const VersionInfo& version);
/// Fields in the order MODL LASR SCSP MESM SBPS TIME STAT (TIME as 6
/// upper-case hex digits, as in the spec's example "002AA9").
std::vector<InfoField> to_info_fields(const StatusInfo& status);

}  // namespace stridemap::scip
