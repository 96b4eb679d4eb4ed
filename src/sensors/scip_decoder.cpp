// Byte-stream side of the SCIP decoder: line assembly across feed() chunks,
// bounded buffers, dropped-byte accounting and event emission. The per-line
// frame grammar is in scip_decoder_lines.cpp.
#include <algorithm>
#include <cstring>
#include <string>
#include <utility>

#include "stridemap/sensors/scip_decoder.hpp"
#include "stridemap/sensors/scip_encoding.hpp"

namespace stridemap::scip {

namespace {

// A data line (65) and any real info line must fit; a frame must hold several lines.
constexpr std::size_t kMinLineBytes = 80;
constexpr std::size_t kMinFrameLines = 4;

}  // namespace

std::string_view error_kind_name(ErrorKind kind) {
  switch (kind) {
    case ErrorKind::garbage: return "garbage";
    case ErrorKind::unknown_echo: return "unknown_echo";
    case ErrorKind::bad_echo_parameters: return "bad_echo_parameters";
    case ErrorKind::unexpected_echo: return "unexpected_echo";
    case ErrorKind::bad_status_line: return "bad_status_line";
    case ErrorKind::unknown_status: return "unknown_status";
    case ErrorKind::bad_checksum: return "bad_checksum";
    case ErrorKind::invalid_character: return "invalid_character";
    case ErrorKind::bad_line_length: return "bad_line_length";
    case ErrorKind::wrong_data_length: return "wrong_data_length";
    case ErrorKind::missing_payload: return "missing_payload";
    case ErrorKind::unexpected_payload: return "unexpected_payload";
    case ErrorKind::bad_info_line: return "bad_info_line";
    case ErrorKind::line_too_long: return "line_too_long";
    case ErrorKind::frame_too_long: return "frame_too_long";
  }
  return "unknown";
}

Decoder::Decoder(const DecoderOptions& options) : options_(options) {
  options_.max_line_bytes = std::max(options_.max_line_bytes, kMinLineBytes);
  options_.max_frame_bytes = std::max(options_.max_frame_bytes, kMinFrameLines * options_.max_line_bytes);
  // A reader feeds what one read returned (the URG driver: up to 4 kB) and
  // decodes it: room for a frame's worth from the start, so that a bigger
  // read later (a host that fell behind) does not allocate mid-stream.
  input_.reserve(options_.max_frame_bytes);
  // A read that ends inside a line leaves its start here until the rest
  // comes (a loaded host reads in smaller pieces); it never grows past a
  // line's limit, so that much room now means no allocation mid-stream.
  partial_line_.reserve(options_.max_line_bytes);
}

void Decoder::feed(std::string_view bytes) {
  if (read_pos_ == input_.size()) {
    input_.clear();
    read_pos_ = 0;
  } else if (read_pos_ > input_.size() / 2) {
    input_.erase(0, read_pos_);
    read_pos_ = 0;
  }
  input_.append(bytes);
}

void Decoder::reset() {
  consumed_ += input_.size() - read_pos_;
  input_.clear();
  read_pos_ = 0;
  partial_line_.clear();
  discarding_line_ = false;
  long_line_held_ = 0;
  state_ = State::idle;
  drop_bytes_ = 0;
  has_held_ = false;
}

bool Decoder::next(Event& out) {
  if (has_held_) {
    std::swap(out, held_);
    has_held_ = false;
    return true;
  }
  out_ = &out;
  produced_ = 0;
  while (produced_ == 0 && read_pos_ < input_.size()) {
    if (discarding_line_) {
      consume_long_line();
      continue;
    }
    const char* begin = input_.data() + read_pos_;
    const std::size_t available = input_.size() - read_pos_;
    const auto* lf = static_cast<const char*>(std::memchr(begin, '\n', available));
    const std::size_t length = lf != nullptr ? static_cast<std::size_t>(lf - begin) : available;
    if (partial_line_.size() + length > options_.max_line_bytes) {
      begin_long_line();
      continue;
    }
    if (lf == nullptr) {
      partial_line_.append(begin, length);
      read_pos_ += length;
      consumed_ += length;
      break;
    }
    const std::size_t line_offset = consumed_ - partial_line_.size();
    std::string_view line(begin, length);
    if (!partial_line_.empty()) {
      partial_line_.append(begin, length);
      line = partial_line_;
    }
    read_pos_ += length + 1;
    consumed_ += length + 1;
    process_line(line, line_offset);
    partial_line_.clear();
  }
  if (read_pos_ == input_.size()) {
    input_.clear();
    read_pos_ = 0;
  }
  out_ = nullptr;
  return produced_ > 0;
}

// A line has outgrown max_line_bytes: the frame it belongs to is dropped and
// the rest of the line is skipped without being stored.
void Decoder::begin_long_line() {
  const std::size_t held = partial_line_.size();
  const std::size_t line_offset = consumed_ - held;
  const std::string message = "no LF within " + std::to_string(options_.max_line_bytes) +
                              " bytes on a line starting at stream offset " + std::to_string(line_offset);
  if (state_ == State::idle) {
    fail(ErrorKind::line_too_long, message, line_offset, 0);
  } else if (state_ != State::dropping) {
    fail(ErrorKind::line_too_long, line_name(frame_lines_ + 1) + ": " + message, line_offset, 0);
  }
  // The bytes already held are counted like the rest of the line, so that
  // the dropped runs are cut at the same places whatever the chunking.
  long_line_held_ = held;
  partial_line_.clear();
  discarding_line_ = true;
}

void Decoder::consume_long_line() {
  const std::size_t room = options_.max_frame_bytes - std::min(drop_bytes_, options_.max_frame_bytes - 1);
  if (long_line_held_ > 0) {
    const std::size_t take = std::min(long_line_held_, room);
    long_line_held_ -= take;
    add_dropped(take);
    return;
  }
  const char* begin = input_.data() + read_pos_;
  const std::size_t available = input_.size() - read_pos_;
  const auto* lf = static_cast<const char*>(std::memchr(begin, '\n', available));
  // Never more than one emission per step: stop at the dropped-run limit.
  const std::size_t take = std::min(lf != nullptr ? static_cast<std::size_t>(lf - begin) + 1 : available, room);
  const bool line_ended = begin[take - 1] == '\n';
  read_pos_ += take;
  consumed_ += take;
  if (line_ended) discarding_line_ = false;
  add_dropped(take);
}

void Decoder::accept_line(std::size_t line_bytes) {
  frame_bytes_ += line_bytes;
  ++frame_lines_;
  if (frame_bytes_ >= options_.max_frame_bytes) {
    fail(ErrorKind::frame_too_long,
         frame_name() + " reached " + std::to_string(frame_bytes_) + " bytes without its blank line (limit " +
             std::to_string(options_.max_frame_bytes) + ")",
         frame_start_ + frame_bytes_, 0);
  }
}

void Decoder::start_frame(std::size_t offset, std::size_t line_bytes, EchoTrust trust) {
  state_ = State::status;
  trust_ = trust;
  frame_start_ = offset;
  frame_bytes_ = 0;
  frame_lines_ = 0;
  have_status_ = false;
  reply_.status.clear();
  reply_.status_checksummed = true;
  accept_line(line_bytes);
}

bool Decoder::is_strict_echo(std::string_view line) {
  // Longest well-formed echo: MD + 13 digits + ';' + 16 tag characters.
  constexpr std::size_t kLongestEcho = 32;
  if (line.size() < 2 || line.size() > kLongestEcho) return false;
  if (line[0] < 'A' || line[0] > 'Z' || line[1] < 'A' || line[1] > 'Z') return false;
  return parse_command(line, scratch_) && scratch_.well_formed;
}

// The current frame (or nothing, from idle) becomes a dropped run that also
// covers `included_bytes` of the current line; dropping goes on until a frame
// boundary.
void Decoder::fail(ErrorKind kind, std::string message, std::size_t problem_offset, std::size_t included_bytes) {
  const bool in_frame = state_ != State::idle && state_ != State::dropping;
  drop_error_.kind = kind;
  drop_error_.message = std::move(message);
  drop_error_.line = in_frame ? frame_lines_ + 1 : 0;
  drop_error_.problem_offset = problem_offset;
  drop_error_.echo = in_frame ? reply_.echo.text : std::string();
  drop_error_.status = in_frame && have_status_ ? reply_.status : std::string();
  if (state_ != State::dropping) {
    drop_start_ = in_frame ? frame_start_ : problem_offset;
    drop_bytes_ = 0;
  }
  state_ = State::dropping;
  add_dropped((in_frame ? frame_bytes_ : 0) + included_bytes);
}

void Decoder::fail_and_close(ErrorKind kind, std::string message, std::size_t problem_offset) {
  fail(kind, std::move(message), problem_offset, 1);
  emit_dropped();
  state_ = State::idle;
}

void Decoder::add_dropped(std::size_t bytes) {
  drop_bytes_ += bytes;
  if (drop_bytes_ < options_.max_frame_bytes) return;
  emit_dropped();
  drop_error_.kind = ErrorKind::frame_too_long;
  drop_error_.message = "still no frame boundary (blank line or echo) after " +
                        std::to_string(options_.max_frame_bytes) + " dropped bytes";
  drop_error_.line = 0;
  drop_error_.problem_offset = drop_start_;
}

void Decoder::emit_dropped() {
  if (drop_bytes_ == 0) return;
  Event& event = next_slot();
  event.kind = EventKind::error;
  event.stream_offset = drop_start_;
  event.byte_count = drop_bytes_;
  DecodeError& error = event.error;
  error.kind = drop_error_.kind;
  error.message = drop_error_.message;
  error.message += " (dropped " + std::to_string(drop_bytes_) + " bytes at stream offsets " +
                   std::to_string(drop_start_) + ".." + std::to_string(drop_start_ + drop_bytes_ - 1) + ")";
  error.line = drop_error_.line;
  error.problem_offset = drop_error_.problem_offset;
  error.echo = drop_error_.echo;
  error.status = drop_error_.status;
  drop_start_ += drop_bytes_;
  drop_bytes_ = 0;
}

void Decoder::emit_reply(EventKind kind) {
  frame_bytes_ += 1;  // the blank line that ends the frame
  Event& event = next_slot();
  event.kind = kind;
  event.stream_offset = frame_start_;
  event.byte_count = frame_bytes_;
  event.reply.echo = reply_.echo;
  event.reply.status = reply_.status;
  event.reply.status_checksummed = reply_.status_checksummed;
  if (kind == EventKind::distance) {
    event.distance.timestamp_ms = timestamp_;
    event.distance.chars_per_value = chars_per_value(reply_.echo.type);
    decode_values(payload_, event.distance.chars_per_value, event.distance.values);
  } else if (kind == EventKind::info) {
    event.info.resize(info_count_);
    for (std::size_t i = 0; i < info_count_; ++i) {
      event.info[i].key = info_[i].key;
      event.info[i].value = info_[i].value;
    }
  } else if (kind == EventKind::time) {
    event.time_ms = timestamp_;
  }
  state_ = State::idle;
}

// At most two events come out of one line (an error for the frame a new echo
// cut short, then an error for that echo's own frame); the second waits here.
Event& Decoder::next_slot() {
  ++produced_;
  if (produced_ == 1) return *out_;
  has_held_ = true;
  return held_;
}

std::string Decoder::frame_name() const {
  constexpr std::size_t kShownEcho = 40;
  const std::string& echo = reply_.echo.text;
  std::string name = "reply '" + echo.substr(0, kShownEcho) + (echo.size() > kShownEcho ? "...'" : "'");
  if (have_status_) name += " (status " + reply_.status + ")";
  return name;
}

std::string Decoder::line_name(std::size_t line_number) const {
  return "line " + std::to_string(line_number) + " of " + frame_name();
}

std::vector<Event> decode_all(std::string_view bytes, const DecoderOptions& options) {
  Decoder decoder(options);
  decoder.feed(bytes);
  std::vector<Event> events;
  Event event;
  while (decoder.next(event)) events.push_back(event);
  return events;
}

}  // namespace stridemap::scip
