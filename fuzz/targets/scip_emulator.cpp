// Host bytes into the URG emulator (sim/urg_emulator.hpp), in pieces and at
// times the input picks. Every reply to a command must be one clean SCIP
// frame (printable bytes, exactly one decoder event covering it, no error)
// that echoes the command it answers: status and info replies come at once,
// in the order of the command lines (GD/GS waiting for their scan
// excepted), single scans echo their GD/GS line, stream frames their MD/MS
// command with the scans-left count. A reply to a line that is no command
// is echoed as it came (unprintable bytes as '?'); the decoder may call it
// an unknown echo or garbage (by design: a codec cannot know what an unknown
// command's reply holds), but its events must end where the reply ends, so
// that the next reply decodes.
#include <algorithm>
#include <deque>
#include <string>

#include "fuzz_input.hpp"
#include "fuzz_target.hpp"
#include "stridemap/core/error.hpp"
#include "stridemap/sensors/scip_command.hpp"
#include "stridemap/sensors/scip_decoder.hpp"
#include "stridemap/sim/urg_emulator.hpp"

namespace {

using namespace stridemap;
using fuzz::check;

class Ramp final : public UrgScanSource {
 public:
  void scan(std::uint64_t index, double, std::vector<std::uint32_t>& values) override {
    values.resize(682);
    for (std::size_t i = 0; i < values.size(); ++i) values[i] = static_cast<std::uint32_t>((i * 7 + index) % 6000);
  }
};

// The command lines as the emulator sees them: cut at CR/LF, at most 64
// bytes, unprintable bytes as '?'.
class Lines {
 public:
  void feed(std::string_view bytes) {
    for (const char c : bytes) {
      if (c == '\n' || c == '\r') {
        if (!partial_.empty()) pending.push_back(partial_);
        partial_.clear();
      } else if (partial_.size() < 64) {
        partial_ += (c < 0x20 || c > 0x7E) ? '?' : c;
      }
    }
  }
  std::deque<std::string> pending;  // lines not answered yet, oldest first

 private:
  std::string partial_;
};

bool is_single_scan(const scip::Command& c) {
  return c.type == scip::CommandType::scan_3char || c.type == scip::CommandType::scan_2char;
}

// Lines before the one a reply echoes got no reply of their own: each must
// be a GD/GS waiting for its scan.
void queue_single_scans_before(Lines& lines, std::deque<std::string>& single_scans, const std::string& echo) {
  while (!lines.pending.empty() && lines.pending.front() != echo) {
    scip::Command c;
    check(scip::parse_command(lines.pending.front(), c) && is_single_scan(c) && c.well_formed,
          "line '" + lines.pending.front() + "' got no reply (the next reply echoes '" + echo + "')");
    single_scans.push_back(lines.pending.front());
    lines.pending.pop_front();
  }
}

}  // namespace

STRIDEMAP_FUZZ_TARGET(scip_emulator) {
  fuzz::ByteReader in(data);
  UrgEmulatorOptions options;
  options.variant = in.byte() % 2 ? UrgVariant::ug01 : UrgVariant::classic;
  options.timestamp_start_ms = (1u << 24) - 1 - in.integer<std::uint16_t>();
  Ramp source;
  UrgEmulator emulator(options, source);
  Lines lines;
  std::deque<std::string> single_scans;  // GD/GS lines waiting for their scan
  std::string stream;                    // the MD/MS line of the running stream
  std::int64_t now = 0, last_sent = 0;
  scip::Event event, first;

  while (!in.empty()) {
    const std::uint8_t op = in.byte();
    if (op % 4 == 3) {
      now += 4 * in.byte();
      emulator.advance(now);
    } else {
      const std::string bytes = in.text(1 + op / 4);
      emulator.advance(now);
      lines.feed(bytes);
      emulator.receive(bytes, now);
    }
    for (const EmulatorOutput& out : emulator.output()) {
      check(out.time_ms >= last_sent, "output out of time order");
      last_sent = out.time_ms;
      for (const char c : out.bytes) check(c == '\n' || (c >= 0x20 && c <= 0x7E), "an unprintable byte sent");
      // What the decoder makes of it: events covering exactly its bytes.
      scip::Decoder decoder;
      decoder.feed(out.bytes);
      std::size_t events = 0, covered = 0;
      std::string decoded;
      while (decoder.next(event)) {
        ++events;
        covered = event.stream_offset + event.byte_count;
        if (event.kind == scip::EventKind::error) decoded += " [" + event.error.message + "]";
        if (events == 1) first = event;
      }
      check(events > 0 && covered == out.bytes.size() && decoder.pending_bytes() == 0,
            "a reply that does not decode as a whole: '" + out.bytes + "'" + decoded);
      const std::string echo = out.bytes.substr(0, out.bytes.find('\n'));
      scip::Command c;
      const bool known = scip::parse_command(echo, c);
      if (known || out.is_scan) {
        check(events == 1 && first.kind != scip::EventKind::error && first.reply.echo.text == echo,
              "the reply to '" + echo + "' is not one clean frame echoing it: '" + out.bytes + "'" + decoded);
      }
      const scip::Event& event = first;

      if (out.is_scan) {
        check(event.kind == scip::EventKind::distance, "a scan that does not decode: " + event.error.message);
        if (is_single_scan(event.reply.echo)) {
          // Its GD/GS line, queued earlier (lines queued before it whose
          // scans a QT or RS cancelled are forgotten with it).
          auto it = std::find(single_scans.begin(), single_scans.end(), echo);
          if (it == single_scans.end()) {
            queue_single_scans_before(lines, single_scans, echo);
            check(!lines.pending.empty() && lines.pending.front() == echo,
                  "a single scan echoing '" + echo + "', which is not waiting");
            lines.pending.pop_front();
          } else {
            single_scans.erase(single_scans.begin(), it + 1);
          }
          continue;
        }
        scip::Command sent;
        check(!stream.empty() && scip::parse_command(stream, sent), "a stream frame without a stream: " + echo);
        const scip::Command& got = event.reply.echo;
        check(got.type == sent.type && got.start_step == sent.start_step && got.end_step == sent.end_step &&
                  got.cluster == sent.cluster && got.scan_interval == sent.scan_interval,
              "stream frame echo '" + echo + "' is not the stream's '" + stream + "'");
        continue;
      }
      // An immediate reply answers the oldest line not answered yet, except
      // GD/GS lines, which were queued for their scan.
      queue_single_scans_before(lines, single_scans, echo);
      check(!lines.pending.empty(), "a reply echoing '" + echo + "', which was not sent");
      const std::string line = lines.pending.front();
      lines.pending.pop_front();
      if (known && c.well_formed && scip::is_stream_command(c.type) && event.reply.status == "00") stream = line;
    }
    emulator.output().clear();
  }
}
