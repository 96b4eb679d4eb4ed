#include "stridemap/sensors/scip_encoding.hpp"

#include <string>

#include "stridemap/core/error.hpp"

namespace stridemap::scip {

std::string describe_byte(char c) {
  static constexpr char kHex[] = "0123456789abcdef";
  const auto byte = static_cast<unsigned char>(c);
  std::string text = "0x";
  text += kHex[byte >> 4];
  text += kHex[byte & 0xF];
  if (byte >= 0x20 && byte < 0x7F) {
    text += " '";
    text += c;
    text += '\'';
  }
  return text;
}

namespace {

void require_width(int chars, int lowest) {
  if (chars < lowest || chars > 4) {
    throw InputError("SCIP encoding: " + std::to_string(chars) + " characters per value is not supported (" +
                     std::to_string(lowest) + "..4)");
  }
}

}  // namespace

char checksum(std::string_view payload) {
  unsigned sum = 0;
  for (const char c : payload) sum += static_cast<unsigned char>(c);
  return static_cast<char>((sum & 0x3Fu) + kFirstDataChar);
}

std::uint32_t max_encodable_value(int chars) {
  require_width(chars, 1);
  return (std::uint32_t{1} << (6 * chars)) - 1u;
}

bool try_decode_value(std::string_view chars, std::uint32_t& value) {
  if (chars.empty() || chars.size() > 4) return false;
  std::uint32_t result = 0;
  for (const char c : chars) {
    if (!is_data_char(c)) return false;
    result = (result << 6) | static_cast<std::uint32_t>(static_cast<unsigned char>(c) - kFirstDataChar);
  }
  value = result;
  return true;
}

std::uint32_t decode_value(std::string_view chars) {
  if (chars.empty() || chars.size() > 4) {
    throw InputError("SCIP value: " + std::to_string(chars.size()) + " characters given, 1..4 expected");
  }
  for (std::size_t i = 0; i < chars.size(); ++i) {
    if (!is_data_char(chars[i])) {
      throw InputError("SCIP value: character " + std::to_string(i) + " is " + describe_byte(chars[i]) +
                       ", outside 0x30..0x6f");
    }
  }
  std::uint32_t value = 0;
  try_decode_value(chars, value);
  return value;
}

void append_encoded_value(std::uint32_t value, int chars, std::string& out) {
  require_width(chars, 2);
  if (value > max_encodable_value(chars)) {
    throw InputError("SCIP value " + std::to_string(value) + " does not fit in " + std::to_string(chars) +
                     " characters (max " + std::to_string(max_encodable_value(chars)) + ")");
  }
  for (int shift = 6 * (chars - 1); shift >= 0; shift -= 6) {
    out += static_cast<char>(((value >> shift) & 0x3Fu) + kFirstDataChar);
  }
}

std::string encode_value(std::uint32_t value, int chars) {
  std::string out;
  append_encoded_value(value, chars, out);
  return out;
}

void decode_values(std::string_view payload, int chars_per_value, std::vector<std::uint32_t>& values) {
  require_width(chars_per_value, 2);
  const auto width = static_cast<std::size_t>(chars_per_value);
  if (payload.size() % width != 0) {
    throw InputError("SCIP data: " + std::to_string(payload.size()) + " characters is not a multiple of " +
                     std::to_string(width) + "-character values");
  }
  values.resize(payload.size() / width);
  const auto* bytes = reinterpret_cast<const unsigned char*>(payload.data());
  // Validate with one branch per value rather than per byte: the 64-character
  // alphabet is exactly the bytes whose (byte - 0x30) is below 64.
  for (std::size_t i = 0, pos = 0; i < values.size(); ++i) {
    std::uint32_t value = 0;
    unsigned bad = 0;
    for (std::size_t k = 0; k < width; ++k, ++pos) {
      const unsigned digit = static_cast<unsigned>(bytes[pos]) - kFirstDataChar;
      bad |= digit;
      value = (value << 6) | (digit & 0x3Fu);
    }
    if (bad > 0x3Fu) {
      for (std::size_t k = i * width; k < (i + 1) * width; ++k) {
        if (!is_data_char(payload[k])) {
          throw InputError("SCIP data: character at offset " + std::to_string(k) + " is " +
                           describe_byte(payload[k]) + ", outside 0x30..0x6f");
        }
      }
    }
    values[i] = value;
  }
}

}  // namespace stridemap::scip
