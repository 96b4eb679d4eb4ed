#pragma once
// What a SCIP 2.0 reply carries once its framing and checksums have been
// checked: the echoed command, the status, and the payload of the replies
// that have one (distance data, KEY:value information lines, a time).
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "stridemap/sensors/scip_command.hpp"

namespace stridemap::scip {

/// Echo and status, common to every reply.
struct Reply {
  Command echo;        ///< the echoed command line, parsed
  std::string status;  ///< two characters ("00", "99", "0E"...), or one for a SCIP 1.1 status
  /// The status line had a checksum and it matched. False only for a
  /// one-character SCIP 1.1 status, which has none.
  bool status_checksummed = true;
};

/// True when the status means the command took effect (see status_means_success).
bool succeeded(const Reply& reply);

/// True for the reply to SCIP2.0 that means "now in SCIP 2.0": '0' from a
/// URG-04LX that was in SCIP 1.1, "0E" from a UG01 that speaks SCIP 2.0
/// natively, or "00".
bool switched_to_scip2(const Reply& reply);

/// Payload of a GD/GS reply or an MD/MS data frame.
struct DistanceData {
  std::uint32_t timestamp_ms = 0;  ///< raw 24-bit sensor time of step 0 [ms]; wraps every 2^24 ms
  int chars_per_value = 3;         ///< 3 (GD/MD) or 2 (GS/MS)
  /// One value per cluster from the echo's start step, in millimetres; values
  /// below DMIN (20) are the sensor's error codes, kept as sent.
  std::vector<std::uint32_t> values;
};

/// One "KEY:value" line of a VV, PP or II reply (checksum already checked).
struct InfoField {
  std::string key;
  std::string value;
  bool operator==(const InfoField&) const = default;
};

/// The value of the first field named `key`, or nullptr.
const std::string* find_field(const std::vector<InfoField>& fields, std::string_view key);

}  // namespace stridemap::scip
