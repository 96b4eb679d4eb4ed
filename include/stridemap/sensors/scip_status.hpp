#pragma once
// Status codes of SCIP 2.0 replies on the URG-04LX (spec sections 8 and 9):
// which codes a command can return, what they mean, and which ones mean the
// command took effect. Compare both characters: "0E" is an error even though
// a strtol-style parse reads it as 0.
#include <string_view>

#include "stridemap/sensors/scip_command.hpp"

namespace stridemap::scip {

/// True for a one-character status without checksum (the sensor still speaks
/// SCIP 1.1; '0' means OK there).
constexpr bool is_scip11_status(std::string_view status) { return status.size() == 1; }

/// True if `status` is defined for `command`: "00", the generic "0A".."0I",
/// the command's own codes (e.g. GD 01-05, 10, 50-98; MD 01-07, 21-98, 99),
/// or any one-character SCIP 1.1 status ('0'-'9', 'A'-'Z').
bool is_known_status(CommandType command, std::string_view status);

/// Short English meaning, for messages ("laser is off", "undefined command 2").
std::string_view status_meaning(CommandType command, std::string_view status);

/// True when the command took effect or its effect was already in place:
/// "00"; "99" for MD/MS; BM "02" (laser already on); TM "02"/"03" (adjust mode
/// already on/off); SS/CR "03" and HS "02" (already set); and for SCIP2.0 the
/// SCIP 1.1 '0', the UG01's "0E" (it speaks SCIP 2.0 natively) and "00".
bool status_means_success(CommandType command, std::string_view status);

}  // namespace stridemap::scip
