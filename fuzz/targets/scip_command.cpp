// SCIP command lines as the sensor's echo (decoder) and as an emulator's
// input (parse_command), one per input line. A well-formed command must
// re-encode to exactly the same bytes, and a status reply to it must decode
// back to the same echo and status.
#include <string>

#include "fuzz_target.hpp"
#include "stridemap/core/error.hpp"
#include "stridemap/sensors/scip_command.hpp"
#include "stridemap/sensors/scip_decoder.hpp"
#include "stridemap/sensors/scip_reply_encoder.hpp"

namespace {

using namespace stridemap;
using namespace stridemap::scip;

// The encoder's bytes for a parsed command, or "" when it has none.
std::string reencode(const Command& c) {
  const std::string_view tag = c.tag;
  ScanRequest request{c.start_step, c.end_step, c.cluster, chars_per_value(c.type) == 2};
  switch (c.type) {
    case CommandType::version: return version_command(tag);
    case CommandType::parameters: return parameters_command(tag);
    case CommandType::status_info: return status_info_command(tag);
    case CommandType::laser_on: return laser_on_command(tag);
    case CommandType::laser_off: return laser_off_command(tag);
    case CommandType::reset: return reset_command(tag);
    case CommandType::time: return time_command(static_cast<TimeMode>(c.code), tag);
    case CommandType::scan_3char:
    case CommandType::scan_2char:
      return c.end_step < c.start_step ? "" : single_scan_command(request, tag);
    case CommandType::stream_3char:
    case CommandType::stream_2char:
      return c.end_step < c.start_step ? "" : stream_command(request, c.scan_interval, c.scan_count, tag);
    default: return "";
  }
}

// Commands whose successful reply is the status alone.
bool status_only(CommandType type) {
  return type == CommandType::laser_on || type == CommandType::laser_off || type == CommandType::reset;
}

}  // namespace

STRIDEMAP_FUZZ_TARGET(scip_command) {
  const std::string_view text = fuzz::as_text(data);
  Command command;
  std::size_t start = 0;
  while (start <= text.size()) {
    std::size_t end = text.find('\n', start);
    if (end == std::string_view::npos) end = text.size();
    const std::string_view line = text.substr(start, end - start);
    start = end + 1;
    if (!parse_command(line, command)) continue;
    fuzz::check(command.text == line, "the parsed command does not keep its line");
    fuzz::check(echo_matches(command, command), "a command is not its own echo: " + command.text);
    (void)expected_value_count(command);
    if (!command.well_formed) continue;
    const std::string bytes = reencode(command);
    // An empty tag after ';' is well formed but the encoders leave the ';' out.
    if (!bytes.empty() && !(command.has_tag && command.tag.empty())) {
      fuzz::check(bytes == command.text + "\n", "'" + command.text + "' re-encodes as '" + bytes + "'");
    }
    if (status_only(command.type)) {
      std::string reply;
      append_status_reply(command.text, "00", reply);
      const std::vector<Event> events = decode_all(reply);
      fuzz::check(events.size() == 1 && events[0].kind == EventKind::status_reply &&
                      events[0].reply.echo.text == command.text && events[0].reply.status == "00",
                  "the status reply to '" + command.text + "' does not decode back");
    }
  }
}
