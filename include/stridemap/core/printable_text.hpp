#pragma once
// Text quoted from an input (a YAML scalar, a device name, a command-line
// value) can hold any byte. Printed raw, an escape or control byte would be
// obeyed by the user's terminal (clear the screen, retitle the window, hide
// the rest of the message), so every message that quotes input goes through
// printable_text() before it reaches a terminal.
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

namespace stridemap {

/// `text` with every byte a terminal could act on written as `\xHH`:
/// C0 controls but newline, DEL, the C1 controls (raw or UTF-8 encoded) and
/// bytes that are not part of valid UTF-8. Printable ASCII and valid UTF-8
/// letters pass unchanged, so a message that needs no escaping is unchanged.
inline std::string printable_text(std::string_view text) {
  static constexpr char kHex[] = "0123456789abcdef";
  std::string out;
  out.reserve(text.size());
  const auto escape = [&out](unsigned char byte) {
    out += "\\x";
    out += kHex[byte >> 4];
    out += kHex[byte & 0x0f];
  };
  const auto continuation = [&text](std::size_t at) {
    return at < text.size() && (static_cast<unsigned char>(text[at]) & 0xc0) == 0x80;
  };
  std::size_t i = 0;
  while (i < text.size()) {
    const auto byte = static_cast<unsigned char>(text[i]);
    if (byte < 0x80) {
      if ((byte < 0x20 && byte != '\n') || byte == 0x7f) {
        escape(byte);
      } else {
        out += static_cast<char>(byte);
      }
      ++i;
      continue;
    }
    // The length of a well-formed UTF-8 sequence starting here, 0 if none.
    std::size_t length = 0;
    if (byte >= 0xc2 && byte <= 0xdf) length = 2;
    else if (byte >= 0xe0 && byte <= 0xef) length = 3;
    else if (byte >= 0xf0 && byte <= 0xf4) length = 4;
    bool valid = length > 0;
    for (std::size_t k = 1; valid && k < length; ++k) valid = continuation(i + k);
    if (valid && length == 3) {
      const auto second = static_cast<unsigned char>(text[i + 1]);
      valid = !(byte == 0xe0 && second < 0xa0) && !(byte == 0xed && second >= 0xa0);  // overlong, surrogate
    }
    if (valid && length == 4) {
      const auto second = static_cast<unsigned char>(text[i + 1]);
      valid = !(byte == 0xf0 && second < 0x90) && !(byte == 0xf4 && second >= 0x90);  // overlong, > U+10FFFF
    }
    // U+0080..U+009F are the C1 controls (CSI among them) in their UTF-8 form.
    if (valid && byte == 0xc2 && static_cast<unsigned char>(text[i + 1]) < 0xa0) valid = false;
    if (!valid) {
      escape(byte);
      ++i;
      continue;
    }
    out.append(text.substr(i, length));
    i += length;
  }
  return out;
}

}  // namespace stridemap
