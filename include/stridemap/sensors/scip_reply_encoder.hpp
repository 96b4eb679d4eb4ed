#pragma once
// Builds the bytes a URG-04LX sends, for an emulator and for tests: status
// replies, distance replies and MD/MS data frames (64-character data lines
// with checksums), VV/PP/II info replies and the TM1 time reply, each ending
// with the blank line. Appends to `out` so that a caller can reuse one buffer.
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "stridemap/sensors/scip_command.hpp"
#include "stridemap/sensors/scip_reply.hpp"

namespace stridemap::scip {

/// "echo LF status sum LF LF". A one-character status is written without a
/// checksum, as a sensor in SCIP 1.1 does. Throws InputError if the echo holds
/// a byte outside printable ASCII or the status is not 1-2 characters of 0-9, A-Z.
void append_status_reply(std::string_view echo, std::string_view status, std::string& out);

/// Splits `payload` into lines of 64 characters plus checksum (the last one
/// shorter) and appends them, each with its LF.
void append_data_lines(std::string_view payload, std::string& out);

/// GD/GS reply (status 00) or MD/MS data frame (status 99) answering `echo`,
/// with the echo's value width. Throws InputError if `echo` is not a
/// well-formed distance command, the value count differs from
/// expected_value_count(echo), a value does not fit the width (index named) or
/// the timestamp does not fit 24 bits.
void append_distance_reply(const Command& echo, std::uint32_t timestamp_ms, std::span<const std::uint32_t> values,
                           std::string& out);

/// Same frame with free status and width (2 or 3), for fault injection: no
/// check of the value count against the echo.
void append_distance_frame(std::string_view echo, std::string_view status, std::uint32_t timestamp_ms,
                           std::span<const std::uint32_t> values, int chars_per_value, std::string& out);

/// VV/PP/II reply with status 00: one "KEY:value;sum" line per field, the sum
/// over "KEY:value". Throws InputError if a key is empty or holds ':', a
/// byte is not printable ASCII, or a line would exceed the decoder's default
/// DecoderOptions::max_line_bytes (256).
void append_info_reply(std::string_view echo, const std::vector<InfoField>& fields, std::string& out);

/// TM1 reply: status 00 and the 4-character time line.
void append_time_reply(std::string_view echo, std::uint32_t time_ms, std::string& out);

}  // namespace stridemap::scip
