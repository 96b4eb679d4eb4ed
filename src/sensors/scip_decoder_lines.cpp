// Frame grammar of the SCIP decoder, one complete line (without its LF) at a
// time: echo, status, then the payload the command and status call for, then
// a blank line. Any line that breaks the grammar drops the frame; a line that
// is a well-formed echo where the frame cannot go on starts the next frame.
#include <string>

#include "scip_line_grammar.hpp"
#include "stridemap/sensors/scip_decoder.hpp"
#include "stridemap/sensors/scip_encoding.hpp"
#include "stridemap/sensors/scip_status.hpp"

namespace stridemap::scip {

namespace {

using detail::is_status_char;
using detail::kDataCharsPerLine;
using detail::kTimestampChars;

bool is_upper(char c) { return c >= 'A' && c <= 'Z'; }
bool is_printable(char c) { return c >= 0x20 && c <= 0x7E; }

bool looks_like_echo(std::string_view line) {
  if (line.size() < 2 || !is_upper(line[0]) || !is_upper(line[1])) return false;
  for (const char c : line) {
    if (!is_printable(c)) return false;
  }
  return true;
}

std::string quoted(std::string_view text) {
  constexpr std::size_t kShown = 40;
  std::string out = "'";
  for (const char c : text.substr(0, kShown)) {
    if (is_printable(c)) {
      out += c;
    } else {
      out += "\\x" + describe_byte(c).substr(2, 2);
    }
  }
  out += text.size() > kShown ? "...'" : "'";
  return out;
}

std::string at_offset(std::size_t offset) { return " at stream offset " + std::to_string(offset); }

}  // namespace

void Decoder::process_line(std::string_view line, std::size_t offset) {
  switch (state_) {
    case State::idle: process_idle(line, offset); break;
    case State::status: process_status(line, offset); break;
    case State::distance_timestamp: process_distance_timestamp(line, offset); break;
    case State::distance_data: process_distance_data(line, offset); break;
    case State::info: process_info(line, offset); break;
    case State::time: process_time(line, offset); break;
    case State::end: process_end(line, offset); break;
    case State::dropping: process_dropping(line, offset); break;
  }
}

void Decoder::process_idle(std::string_view line, std::size_t offset) {
  if (line.empty()) return;  // extra LFs between frames carry nothing
  if (parse_command(line, reply_.echo)) {
    start_frame(offset, line.size() + 1, reply_.echo.well_formed ? EchoTrust::strict : EchoTrust::lenient);
    return;
  }
  // Bytes glued to the front of an echo (line noise, a partial write).
  const std::size_t start = find_echo_suffix(line, false);
  if (start != std::string_view::npos) {
    fail(ErrorKind::garbage, std::to_string(start) + " bytes of garbage " + quoted(line.substr(0, start)) +
                                 " before the echo " + quoted(line.substr(start)) + at_offset(offset),
         offset, start);
    emit_dropped();
    parse_command(line.substr(start), reply_.echo);
    start_frame(offset + start, line.size() - start + 1, EchoTrust::strict);
    return;
  }
  if (looks_like_echo(line)) {
    start_frame(offset, line.size() + 1, EchoTrust::unknown);  // judged by the next line
    return;
  }
  fail(ErrorKind::garbage, "garbage before a frame: line " + quoted(line) + at_offset(offset) + " is not an echo",
       offset, line.size() + 1);
}

// Where a well-formed echo ends the line after other bytes, or npos. Outside
// a frame boundary only GD/GS/MD/MS echoes count: they are long enough never
// to end a data line by chance, where "QT" would once in a few hundred lines.
std::size_t Decoder::find_echo_suffix(std::string_view line, bool distance_only) {
  for (std::size_t i = 1; i + 1 < line.size(); ++i) {
    const bool candidate = distance_only ? (line[i] == 'G' || line[i] == 'M') && (line[i + 1] == 'D' || line[i + 1] == 'S')
                                         : is_upper(line[i]) && is_upper(line[i + 1]);
    if (candidate && is_strict_echo(line.substr(i)) && (!distance_only || is_distance_command(scratch_.type))) {
      return i;
    }
  }
  return std::string_view::npos;
}

// A well-formed echo (alone, or ending the line after the frame's damaged
// last bytes) where the current frame expected something else: the frame is
// cut short and the echo starts the next one.
bool Decoder::restart_if_echo(std::string_view line, std::size_t offset) {
  const std::size_t start = is_strict_echo(line) ? 0 : find_echo_suffix(line, true);
  if (start == std::string_view::npos) return false;
  const std::string_view echo = line.substr(start);
  const bool trusted = trust_ == EchoTrust::strict;
  fail(trusted ? ErrorKind::unexpected_echo : ErrorKind::garbage,
       trusted ? line_name(frame_lines_ + 1) + " holds the echo " + quoted(echo) + " of a new reply" +
                     at_offset(offset + start) + ": the frame ended without its blank line"
               : "garbage before a frame: line " + quoted(reply_.echo.text) + " is not followed by a status line",
       offset + start, start);
  emit_dropped();
  parse_command(echo, reply_.echo);
  start_frame(offset + start, echo.size() + 1, EchoTrust::strict);
  return true;
}

void Decoder::process_status(std::string_view line, std::size_t offset) {
  const bool scip11 = line.size() == 1 && is_status_char(line[0]);
  const bool checked = line.size() == 3 && is_status_char(line[0]) && is_status_char(line[1]) &&
                       checksum(line.substr(0, 2)) == line[2];
  if (!scip11 && !checked) {
    if (restart_if_echo(line, offset)) return;
    if (trust_ != EchoTrust::strict) {
      const std::string message = "garbage before a frame: line " + quoted(reply_.echo.text) + at_offset(frame_start_) +
                                  " is not followed by a status line";
      if (line.empty()) {
        fail_and_close(ErrorKind::garbage, message, frame_start_);
      } else {
        fail(ErrorKind::garbage, message, frame_start_, line.size() + 1);
      }
      return;
    }
    const std::string where = line_name(2) + at_offset(offset);
    if (line.empty()) {
      fail_and_close(ErrorKind::bad_status_line, frame_name() + " ended after its echo without a status line", offset);
    } else if (line.size() == 3 && is_status_char(line[0]) && is_status_char(line[1])) {
      fail(ErrorKind::bad_checksum, "bad checksum on " + where + ": expected '" + checksum(line.substr(0, 2)) +
                                        "', found " + describe_byte(line[2]),
           offset, line.size() + 1);
    } else if (line.size() == 3 || line.size() == 1) {
      fail(ErrorKind::invalid_character, "invalid status " + quoted(line) + " on " + where +
                                             ": status characters are 0-9 and A-Z", offset, line.size() + 1);
    } else {
      fail(ErrorKind::bad_status_line, "status line " + quoted(line) + " on " + where + " has " +
                                           std::to_string(line.size()) + " characters, expected 3 (or 1 in SCIP 1.1)",
           offset, line.size() + 1);
    }
    return;
  }
  reply_.status.assign(line.substr(0, scip11 ? 1 : 2));
  reply_.status_checksummed = !scip11;
  have_status_ = true;
  const CommandType type = reply_.echo.type;
  if (trust_ == EchoTrust::unknown) {
    fail(ErrorKind::unknown_echo, "reply to an unknown command: echo " + quoted(reply_.echo.text) +
                                      at_offset(frame_start_) + " with status " + quoted(reply_.status),
         frame_start_, line.size() + 1);
    return;
  }
  if (!is_known_status(type, reply_.status)) {
    fail(ErrorKind::unknown_status, "unknown status " + quoted(reply_.status) + " for command " +
                                        std::string(command_code(type)) + " on " + line_name(2) + at_offset(offset),
         offset, line.size() + 1);
    return;
  }
  accept_line(line.size() + 1);
  if (state_ == State::status) begin_body();
}

// Chooses what follows the status line: distance data, info lines, a time, or
// nothing but the blank line.
void Decoder::begin_body() {
  const CommandType type = reply_.echo.type;
  const std::string& status = reply_.status;
  state_ = State::end;
  if (is_distance_command(type) && status == (is_stream_command(type) ? "99" : "00")) {
    const int count = expected_value_count(reply_.echo);
    if (!reply_.echo.well_formed || count <= 0) {
      const std::string why = reply_.echo.well_formed ? "end step is before start step" : reply_.echo.problem;
      fail(ErrorKind::bad_echo_parameters,
           frame_name() + at_offset(frame_start_) + " carries data but its echo cannot size it: " + why,
           frame_start_, 0);
      return;
    }
    expected_chars_ = static_cast<std::size_t>(count) * static_cast<std::size_t>(chars_per_value(type));
    payload_.clear();
    have_short_line_ = false;
    state_ = State::distance_timestamp;
  } else if ((type == CommandType::version || type == CommandType::parameters ||
              type == CommandType::status_info) && status == "00") {
    info_count_ = 0;
    state_ = State::info;
  } else if (type == CommandType::time && reply_.echo.code == 1 && status == "00") {
    have_time_ = false;
    state_ = State::time;
  }
}

// Payload characters then one checksum character, all in 0x30..0x6f.
bool Decoder::check_data_line(std::string_view line, std::size_t offset, std::string_view what) {
  const std::size_t payload = line.size() - 1;
  unsigned sum = 0;
  unsigned outside = 0;
  for (std::size_t i = 0; i < payload; ++i) {
    const unsigned byte = static_cast<unsigned char>(line[i]);
    sum += byte;
    outside |= byte - kFirstDataChar;  // wraps to a large value below 0x30
  }
  const char expected = static_cast<char>((sum & 0x3Fu) + kFirstDataChar);
  if (outside <= 0x3Fu && expected == line[payload]) return true;
  if (restart_if_echo(line, offset)) return false;
  const std::string where = line_name(frame_lines_ + 1) + " (" + std::string(what) + ")";
  for (std::size_t i = 0; i < payload; ++i) {
    if (!is_data_char(line[i])) {
      fail(ErrorKind::invalid_character, "invalid character " + describe_byte(line[i]) + " at column " +
                                             std::to_string(i + 1) + " of " + where + at_offset(offset + i),
           offset + i, line.size() + 1);
      return false;
    }
  }
  fail(ErrorKind::bad_checksum, "bad checksum on " + where + at_offset(offset) + ": expected '" + expected +
                                    "', found " + describe_byte(line[payload]),
       offset, line.size() + 1);
  return false;
}

void Decoder::process_distance_timestamp(std::string_view line, std::size_t offset) {
  if (line.empty()) {
    fail_and_close(ErrorKind::missing_payload, frame_name() + " ended without its timestamp line", offset);
    return;
  }
  if (line.size() != kTimestampChars + 1) {
    if (restart_if_echo(line, offset)) return;
    fail(ErrorKind::bad_line_length, "timestamp " + line_name(3) + at_offset(offset) + " has " +
                                         std::to_string(line.size()) + " characters, expected 5",
         offset, line.size() + 1);
    return;
  }
  if (!check_data_line(line, offset, "timestamp")) return;
  try_decode_value(line.substr(0, kTimestampChars), timestamp_);
  accept_line(line.size() + 1);
  if (state_ == State::distance_timestamp) state_ = State::distance_data;
}

void Decoder::process_distance_data(std::string_view line, std::size_t offset) {
  if (line.empty()) {
    finish_distance();
    return;
  }
  if (have_short_line_) {
    // Only the last data line may be short, so this frame lost its blank
    // line; the short line may itself have been the next echo.
    if (is_strict_echo(short_line_)) {
      const std::size_t echo_bytes = short_line_.size() + 1;
      frame_bytes_ -= echo_bytes;
      --frame_lines_;
      fail(ErrorKind::unexpected_echo, line_name(frame_lines_ + 1) + " is the echo " + quoted(short_line_) +
                                           " of a new reply" + at_offset(short_line_offset_) +
                                           ": the frame ended without its blank line",
           short_line_offset_, 0);
      emit_dropped();
      parse_command(short_line_, reply_.echo);
      start_frame(short_line_offset_, echo_bytes, EchoTrust::strict);
      process_line(line, offset);  // this line belongs to the new frame
      return;
    }
    if (restart_if_echo(line, offset)) return;
    fail(ErrorKind::bad_line_length, "data " + line_name(frame_lines_) + at_offset(short_line_offset_) + " has " +
                                         std::to_string(short_line_.size() - 1) +
                                         " data characters but is not the last line (only the last may have fewer than 64)",
         short_line_offset_, line.size() + 1);
    return;
  }
  if (line.size() < 2 || line.size() > kDataCharsPerLine + 1) {
    if (restart_if_echo(line, offset)) return;
    fail(ErrorKind::bad_line_length, "data " + line_name(frame_lines_ + 1) + at_offset(offset) + " has " +
                                         std::to_string(line.size()) + " characters, expected 2..65",
         offset, line.size() + 1);
    return;
  }
  if (!check_data_line(line, offset, "data")) return;
  const std::size_t chars = line.size() - 1;
  if (payload_.size() + chars > expected_chars_) {
    if (restart_if_echo(line, offset)) return;
    fail(ErrorKind::wrong_data_length, "wrong data length in " + frame_name() + ": the echo announces " +
                                           std::to_string(expected_chars_) + " data characters, but line " +
                                           std::to_string(frame_lines_ + 1) + at_offset(offset) + " brings it to " +
                                           std::to_string(payload_.size() + chars),
         offset, line.size() + 1);
    return;
  }
  payload_.append(line.data(), chars);
  if (chars < kDataCharsPerLine) {
    have_short_line_ = true;
    short_line_.assign(line);
    short_line_offset_ = offset;
  }
  accept_line(line.size() + 1);
}

void Decoder::finish_distance() {
  if (payload_.size() != expected_chars_) {
    const auto width = static_cast<std::size_t>(chars_per_value(reply_.echo.type));
    fail_and_close(ErrorKind::wrong_data_length,
                   "wrong data length in " + frame_name() + at_offset(frame_start_) + ": expected " +
                       std::to_string(expected_chars_ / width) + " values (" + std::to_string(expected_chars_) +
                       " characters) from the echo, got " + std::to_string(payload_.size()) + " characters",
                   frame_start_ + frame_bytes_);
    return;
  }
  emit_reply(EventKind::distance);
}

// "KEY:value;sum", printable ASCII; the sum covers "KEY:value" (the sensor's
// way) or "KEY:value;" (accepted, as the official library does).
bool Decoder::check_info_line(std::string_view line, std::size_t offset, std::size_t& colon) {
  const std::size_t n = line.size();
  std::string problem;
  ErrorKind kind = ErrorKind::bad_info_line;
  colon = line.find(':');
  for (std::size_t i = 0; i < n && problem.empty(); ++i) {
    if (!is_printable(line[i])) {
      kind = ErrorKind::invalid_character;
      problem = "invalid character " + describe_byte(line[i]) + " at column " + std::to_string(i + 1);
    }
  }
  if (problem.empty() && (n < 3 || line[n - 2] != ';' || colon == 0 || colon == std::string_view::npos ||
                          colon > n - 2)) {
    problem = quoted(line) + " is not KEY:value;sum";
  }
  if (problem.empty()) {
    const char sum = line[n - 1];
    if (checksum(line.substr(0, n - 2)) == sum || checksum(line.substr(0, n - 1)) == sum) return true;
    kind = ErrorKind::bad_checksum;
    problem = "bad checksum: expected '" + std::string(1, checksum(line.substr(0, n - 2))) + "', found " +
              describe_byte(sum);
  }
  if (restart_if_echo(line, offset)) return false;
  fail(kind, line_name(frame_lines_ + 1) + at_offset(offset) + ": " + problem, offset, n + 1);
  return false;
}

void Decoder::process_info(std::string_view line, std::size_t offset) {
  if (line.empty()) {
    emit_reply(EventKind::info);
    return;
  }
  std::size_t colon = 0;
  if (!check_info_line(line, offset, colon)) return;
  if (info_.size() <= info_count_) info_.resize(info_count_ + 1);
  info_[info_count_].key.assign(line.substr(0, colon));
  info_[info_count_].value.assign(line.substr(colon + 1, line.size() - 2 - (colon + 1)));
  ++info_count_;
  accept_line(line.size() + 1);
}

void Decoder::process_time(std::string_view line, std::size_t offset) {
  if (line.empty()) {
    if (have_time_) {
      emit_reply(EventKind::time);
    } else {
      fail_and_close(ErrorKind::missing_payload, frame_name() + " ended without its time line", offset);
    }
    return;
  }
  if (have_time_ || line.size() != kTimestampChars + 1) {
    if (restart_if_echo(line, offset)) return;
    fail(have_time_ ? ErrorKind::unexpected_payload : ErrorKind::bad_line_length,
         line_name(frame_lines_ + 1) + at_offset(offset) + " has " + std::to_string(line.size()) +
             (have_time_ ? " characters after the time line, expected the blank line"
                         : " characters, expected a 5-character time line"),
         offset, line.size() + 1);
    return;
  }
  if (!check_data_line(line, offset, "time")) return;
  try_decode_value(line.substr(0, kTimestampChars), timestamp_);
  have_time_ = true;
  accept_line(line.size() + 1);
}

void Decoder::process_end(std::string_view line, std::size_t offset) {
  if (line.empty()) {
    emit_reply(EventKind::status_reply);
    return;
  }
  if (restart_if_echo(line, offset)) return;
  fail(ErrorKind::unexpected_payload, frame_name() + " carries no data, but " + line_name(frame_lines_ + 1) +
                                          at_offset(offset) + " is " + quoted(line) + " instead of the blank line",
       offset, line.size() + 1);
}

void Decoder::process_dropping(std::string_view line, std::size_t offset) {
  if (line.empty()) {
    add_dropped(1);
    emit_dropped();
    state_ = State::idle;
    return;
  }
  const std::size_t start = is_strict_echo(line) ? 0 : find_echo_suffix(line, true);
  if (start == std::string_view::npos) {
    add_dropped(line.size() + 1);
    return;
  }
  add_dropped(start);
  emit_dropped();
  parse_command(line.substr(start), reply_.echo);
  start_frame(offset + start, line.size() - start + 1, EchoTrust::strict);
}

}  // namespace stridemap::scip
