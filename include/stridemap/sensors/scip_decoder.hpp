#pragma once
// Streaming decoder for the bytes a URG-04LX sends. Feed it bytes in any
// chunking; pull events: complete replies (status-only, distance, info, time)
// and errors. Every malformed frame becomes one error event saying what was
// wrong and which bytes were dropped; decoding resynchronises at the next
// frame boundary (a blank line, or an echo line where a frame cannot go on),
// so the frames around a bad one are kept. Memory stays bounded whatever the
// input. Pure code, no I/O; see docs/scip.md.
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "stridemap/sensors/scip_reply.hpp"

namespace stridemap::scip {

enum class EventKind : std::uint8_t {
  status_reply,  ///< reply without payload: BM, QT, RS, MD/MS ack, SCIP2.0, TM0/2, errors of any command
  distance,      ///< GD/GS reply (status 00) or MD/MS data frame (status 99)
  info,          ///< VV, PP or II reply: KEY:value fields
  time,          ///< TM1 reply: sensor time
  error          ///< malformed bytes, dropped (see DecodeError)
};

/// What was wrong with dropped bytes. The first problem found names the error.
enum class ErrorKind : std::uint8_t {
  garbage,              ///< bytes outside any frame (before an echo line)
  unknown_echo,         ///< a reply to a command this codec does not know
  bad_echo_parameters,  ///< echo parameters unusable for a reply that needs them (e.g. GD data, end < start)
  unexpected_echo,      ///< an echo line where the frame had not ended (missing blank line)
  bad_status_line,      ///< status line missing or not 1 or 3 characters
  unknown_status,       ///< status not defined for the command
  bad_checksum,         ///< a line's checksum character does not match
  invalid_character,    ///< byte outside 0x30..0x6f in encoded data (or outside printable ASCII in an info line)
  bad_line_length,      ///< timestamp or data line of the wrong length
  wrong_data_length,    ///< value count differs from the echo's ceil((end-start+1)/cluster)
  missing_payload,      ///< a reply that needs data ended without it
  unexpected_payload,   ///< lines after a status that carries no data
  bad_info_line,        ///< VV/PP/II line not "KEY:value;sum"
  line_too_long,        ///< no LF within DecoderOptions::max_line_bytes
  frame_too_long        ///< frame or run of dropped bytes reached DecoderOptions::max_frame_bytes
};

std::string_view error_kind_name(ErrorKind kind);

struct DecodeError {
  ErrorKind kind = ErrorKind::garbage;
  /// Full sentence naming the reply, the line, the byte offset and what was
  /// expected versus found.
  std::string message;
  std::size_t line = 0;            ///< 1-based line within the frame (1 = echo); 0 when not in a frame
  std::size_t problem_offset = 0;  ///< stream offset of the offending byte or line
  std::string echo;                ///< echo line of the dropped frame, if one was read
  std::string status;              ///< its status, if one was read
};

/// One decoded item. Reused between calls: only the members of `kind` are
/// meaningful (reply: every kind but error), the others keep stale contents
/// so that their storage is reused.
struct Event {
  EventKind kind = EventKind::error;
  std::size_t stream_offset = 0;  ///< stream offset of the first byte covered
  std::size_t byte_count = 0;     ///< bytes covered, terminating LFs included
  Reply reply;
  DistanceData distance;
  std::vector<InfoField> info;
  std::uint32_t time_ms = 0;  ///< TM1: raw 24-bit sensor time [ms]
  DecodeError error;
};

struct DecoderOptions {
  /// A line (echo, status, data, info) longer than this without LF is
  /// dropped as line_too_long. Real lines have at most 65 data characters;
  /// info lines are below 100.
  std::size_t max_line_bytes = 256;
  /// A frame, or a run of dropped bytes, reaching this size is reported and
  /// cut (frame_too_long); a 769-step 3-character scan is about 2.4 kB.
  std::size_t max_frame_bytes = 16384;
};

class Decoder {
 public:
  explicit Decoder(const DecoderOptions& options = {});

  /// Queues bytes. Nothing is decoded until next() is called.
  void feed(std::string_view bytes);
  /// Decodes queued bytes until one event is complete; returns false when the
  /// queued bytes are used up (a partial frame stays pending for later bytes).
  /// Reuses out's storage.
  bool next(Event& out);
  /// Forgets queued bytes and any partial frame; stream offsets keep counting.
  void reset();

  /// Bytes consumed so far (offset of the next byte to be decoded).
  std::size_t stream_offset() const { return consumed_; }
  /// Bytes queued by feed() and not yet decoded.
  std::size_t pending_bytes() const { return input_.size() - read_pos_; }
  const DecoderOptions& options() const { return options_; }

 private:
  enum class State : std::uint8_t { idle, status, distance_timestamp, distance_data, info, time, end, dropping };
  enum class EchoTrust : std::uint8_t { strict, lenient, unknown };

  void process_line(std::string_view line, std::size_t offset);
  void process_idle(std::string_view line, std::size_t offset);
  void process_status(std::string_view line, std::size_t offset);
  void process_distance_timestamp(std::string_view line, std::size_t offset);
  void process_distance_data(std::string_view line, std::size_t offset);
  void process_info(std::string_view line, std::size_t offset);
  void process_time(std::string_view line, std::size_t offset);
  void process_end(std::string_view line, std::size_t offset);
  void process_dropping(std::string_view line, std::size_t offset);

  void start_frame(std::size_t offset, std::size_t line_bytes, EchoTrust trust);
  void accept_line(std::size_t line_bytes);
  void begin_body();
  bool restart_if_echo(std::string_view line, std::size_t offset);
  bool check_data_line(std::string_view line, std::size_t offset, std::string_view what);
  bool check_info_line(std::string_view line, std::size_t offset, std::size_t& colon);
  void finish_distance();
  void emit_reply(EventKind kind);
  void fail(ErrorKind kind, std::string message, std::size_t problem_offset, std::size_t included_bytes);
  void fail_and_close(ErrorKind kind, std::string message, std::size_t problem_offset);
  void add_dropped(std::size_t bytes);
  void emit_dropped();
  void begin_long_line();
  void consume_long_line();
  std::string frame_name() const;
  std::string line_name(std::size_t line_number) const;
  Event& next_slot();
  bool is_strict_echo(std::string_view line);
  std::size_t find_echo_suffix(std::string_view line, bool distance_only);

  DecoderOptions options_;
  std::string input_;
  std::size_t read_pos_ = 0;
  std::size_t consumed_ = 0;  ///< stream offset of input_[read_pos_]
  std::string partial_line_;  ///< bytes of a line whose LF has not arrived
  bool discarding_line_ = false;
  std::size_t long_line_held_ = 0;  ///< bytes of an over-long line not yet counted as dropped

  State state_ = State::idle;
  EchoTrust trust_ = EchoTrust::strict;
  std::size_t frame_start_ = 0;
  std::size_t frame_bytes_ = 0;
  std::size_t frame_lines_ = 0;
  Reply reply_;
  bool have_status_ = false;
  bool have_time_ = false;
  std::string payload_;                ///< data characters, checksums stripped
  std::size_t expected_chars_ = 0;
  std::uint32_t timestamp_ = 0;
  std::vector<InfoField> info_;
  std::size_t info_count_ = 0;
  std::string short_line_;             ///< last data line if shorter than 64 characters
  std::size_t short_line_offset_ = 0;
  bool have_short_line_ = false;

  std::size_t drop_start_ = 0;
  std::size_t drop_bytes_ = 0;
  DecodeError drop_error_;

  Command scratch_;
  Event* out_ = nullptr;
  Event held_;
  int produced_ = 0;
  bool has_held_ = false;
};

/// Decodes a whole byte string (convenience for tests and tools; allocates).
std::vector<Event> decode_all(std::string_view bytes, const DecoderOptions& options = {});

}  // namespace stridemap::scip
