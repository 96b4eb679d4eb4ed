#include "stridemap/sensors/scip_reply_encoder.hpp"

#include <string>

#include "scip_line_grammar.hpp"
#include "stridemap/core/error.hpp"
#include "stridemap/sensors/scip_decoder.hpp"
#include "stridemap/sensors/scip_encoding.hpp"

namespace stridemap::scip {

namespace {

constexpr int kTimestampCharCount = static_cast<int>(detail::kTimestampChars);
constexpr std::size_t kMaxInfoLineBytes = DecoderOptions{}.max_line_bytes;

void require_printable(std::string_view text, std::string_view what) {
  for (std::size_t i = 0; i < text.size(); ++i) {
    if (text[i] < 0x20 || text[i] > 0x7E) {
      throw InputError("SCIP reply encoder: " + std::string(what) + " character " + std::to_string(i) + " is " +
                       describe_byte(text[i]) + ", not printable ASCII");
    }
  }
}

void append_echo_and_status(std::string_view echo, std::string_view status, std::string& out) {
  require_printable(echo, "echo");
  if (status.empty() || status.size() > 2 || !detail::is_status_char(status[0]) ||
      (status.size() == 2 && !detail::is_status_char(status[1]))) {
    throw InputError("SCIP reply encoder: status '" + std::string(status) +
                     "' is not 2 characters of 0-9/A-Z (or 1 for SCIP 1.1)");
  }
  out += echo;
  out += '\n';
  out += status;
  if (status.size() == 2) out += checksum(status);
  out += '\n';
}

void append_checked_line(std::string_view payload, std::string& out) {
  out += payload;
  out += checksum(payload);
  out += '\n';
}

void append_timestamp_line(std::uint32_t time_ms, std::string& out) {
  if (time_ms > max_encodable_value(kTimestampCharCount)) {
    throw InputError("SCIP reply encoder: time " + std::to_string(time_ms) + " ms does not fit 24 bits");
  }
  const std::size_t start = out.size();
  append_encoded_value(time_ms, kTimestampCharCount, out);
  out += checksum(std::string_view(out).substr(start));
  out += '\n';
}

}  // namespace

void append_status_reply(std::string_view echo, std::string_view status, std::string& out) {
  append_echo_and_status(echo, status, out);
  out += '\n';
}

void append_data_lines(std::string_view payload, std::string& out) {
  for (std::size_t pos = 0; pos < payload.size(); pos += detail::kDataCharsPerLine) {
    append_checked_line(payload.substr(pos, detail::kDataCharsPerLine), out);
  }
}

void append_distance_frame(std::string_view echo, std::string_view status, std::uint32_t timestamp_ms,
                           std::span<const std::uint32_t> values, int chars_per_value, std::string& out) {
  if (chars_per_value != 2 && chars_per_value != 3) {
    throw InputError("SCIP reply encoder: " + std::to_string(chars_per_value) +
                     " characters per value; distance data uses 2 or 3");
  }
  const std::uint32_t largest = max_encodable_value(chars_per_value);
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (values[i] > largest) {
      throw InputError("SCIP reply encoder: value " + std::to_string(values[i]) + " mm at index " +
                       std::to_string(i) + " does not fit " + std::to_string(chars_per_value) +
                       " characters (max " + std::to_string(largest) + ")");
    }
  }
  if (timestamp_ms > max_encodable_value(kTimestampCharCount)) {
    throw InputError("SCIP reply encoder: timestamp " + std::to_string(timestamp_ms) + " ms does not fit 24 bits");
  }
  append_echo_and_status(echo, status, out);
  append_timestamp_line(timestamp_ms, out);
  // Encode straight into the output and insert a checksum after every 64
  // data characters: values straddle line ends (64 is not a multiple of 3).
  const auto width = static_cast<std::size_t>(chars_per_value);
  out.reserve(out.size() + values.size() * width * 66 / 64 + 4);
  std::size_t line_start = out.size();
  for (const std::uint32_t value : values) {
    for (std::size_t k = width; k-- > 0;) {
      out += static_cast<char>(((value >> (6 * k)) & 0x3Fu) + kFirstDataChar);
      if (out.size() - line_start == detail::kDataCharsPerLine) {
        out += checksum(std::string_view(out).substr(line_start));
        out += '\n';
        line_start = out.size();
      }
    }
  }
  if (out.size() > line_start) {
    out += checksum(std::string_view(out).substr(line_start));
    out += '\n';
  }
  out += '\n';
}

void append_distance_reply(const Command& echo, std::uint32_t timestamp_ms, std::span<const std::uint32_t> values,
                           std::string& out) {
  if (!is_distance_command(echo.type) || !echo.well_formed) {
    throw InputError("SCIP reply encoder: '" + echo.text + "' is not a well-formed GD/GS/MD/MS command" +
                     (echo.problem.empty() ? std::string() : " (" + echo.problem + ")"));
  }
  const int expected = expected_value_count(echo);
  if (values.size() != static_cast<std::size_t>(expected)) {
    throw InputError("SCIP reply encoder: '" + echo.text + "' needs " + std::to_string(expected) + " values, " +
                     std::to_string(values.size()) + " given");
  }
  append_distance_frame(echo.text, is_stream_command(echo.type) ? "99" : "00", timestamp_ms, values,
                        chars_per_value(echo.type), out);
}

void append_info_reply(std::string_view echo, const std::vector<InfoField>& fields, std::string& out) {
  for (const auto& field : fields) {
    if (field.key.empty() || field.key.find(':') != std::string::npos) {
      throw InputError("SCIP reply encoder: info key '" + field.key + "' is empty or holds ':'");
    }
    require_printable(field.key, "info key");
    require_printable(field.value, "info value of " + field.key);
    // "KEY:value;sum": a longer line than a decoder accepts would be dropped
    // as line_too_long at the other end.
    const std::size_t line_bytes = field.key.size() + field.value.size() + 3;
    if (line_bytes > kMaxInfoLineBytes) {
      throw InputError("SCIP reply encoder: info line of " + field.key + " would be " + std::to_string(line_bytes) +
                       " bytes, more than the " + std::to_string(kMaxInfoLineBytes) + " a decoder accepts");
    }
  }
  append_echo_and_status(echo, "00", out);
  std::string line;
  for (const auto& field : fields) {
    line = field.key + ':' + field.value;
    out += line;
    out += ';';
    out += checksum(line);
    out += '\n';
  }
  out += '\n';
}

void append_time_reply(std::string_view echo, std::uint32_t time_ms, std::string& out) {
  if (time_ms > max_encodable_value(kTimestampCharCount)) {
    throw InputError("SCIP reply encoder: time " + std::to_string(time_ms) + " ms does not fit 24 bits");
  }
  append_echo_and_status(echo, "00", out);
  append_timestamp_line(time_ms, out);
  out += '\n';
}

}  // namespace stridemap::scip
