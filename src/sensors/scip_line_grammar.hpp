#pragma once
// Facts of the SCIP 2.0 line grammar that the decoder, the reply encoder and
// the status table share (internal to the sensors layer).
#include <cstddef>

namespace stridemap::scip::detail {

/// Encoded data characters on one full data line, before its checksum.
inline constexpr std::size_t kDataCharsPerLine = 64;
/// Encoded characters of a reply's timestamp.
inline constexpr std::size_t kTimestampChars = 4;

/// A status character: a decimal digit or an upper-case letter.
inline constexpr bool is_status_char(char c) { return (c >= '0' && c <= '9') || (c >= 'A' && c <= 'Z'); }

}  // namespace stridemap::scip::detail
