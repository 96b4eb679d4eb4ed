#pragma once
// SCIP 2.0 character encodings and checksums (Hokuyo C-42-03320B section 6/7):
// a number is sent as 2, 3 or 4 characters, each carrying 6 bits as
// (character - 0x30), most significant first; a line carries a one-character
// checksum ((sum of its bytes) & 0x3F) + 0x30. Pure functions, no I/O.
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace stridemap::scip {

/// Lowest and highest byte that can appear in encoded data or as a checksum.
inline constexpr unsigned char kFirstDataChar = 0x30;  // '0'
inline constexpr unsigned char kLastDataChar = 0x6F;   // 'o'

/// True for the 64 characters 0x30..0x6F that carry 6 bits each.
constexpr bool is_data_char(char c) {
  const auto byte = static_cast<unsigned char>(c);
  return byte >= kFirstDataChar && byte <= kLastDataChar;
}

/// A byte for messages: "0x41 'A'" (printable) or "0x0d".
std::string describe_byte(char c);

/// Checksum character of a line payload: ((sum of bytes) & 0x3F) + 0x30.
char checksum(std::string_view payload);

/// Largest value that fits in `chars` characters (2: 4095, 3: 262143, 4: 16777215).
std::uint32_t max_encodable_value(int chars);

/// Decodes 1..4 data characters. Returns false (leaving `value` untouched) if
/// the length is outside 1..4 or a character is outside 0x30..0x6F.
bool try_decode_value(std::string_view chars, std::uint32_t& value);

/// As try_decode_value, but throws InputError naming the offending character
/// and its position.
std::uint32_t decode_value(std::string_view chars);

/// Appends `value` as `chars` characters (2..4). Throws InputError if the value
/// does not fit.
void append_encoded_value(std::uint32_t value, int chars, std::string& out);
std::string encode_value(std::uint32_t value, int chars);

/// Decodes a concatenated payload (checksums already stripped) of
/// `chars_per_value`-character values into `values` (resized, storage reused).
/// Throws InputError if the payload length is not a multiple of the value
/// width or a character is invalid (naming its offset).
void decode_values(std::string_view payload, int chars_per_value, std::vector<std::uint32_t>& values);

}  // namespace stridemap::scip
