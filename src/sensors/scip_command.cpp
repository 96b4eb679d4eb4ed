#include "stridemap/sensors/scip_command.hpp"

#include <array>
#include <string>
#include <utility>

#include "stridemap/core/error.hpp"

namespace stridemap::scip {

namespace {

constexpr std::string_view kSwitchCode = "SCIP2.0";
constexpr std::size_t kMaxTagChars = 16;

struct CodeEntry {
  std::string_view code;
  CommandType type;
};

constexpr std::array<CodeEntry, 15> kCodes{{
    {"VV", CommandType::version},       {"PP", CommandType::parameters},   {"II", CommandType::status_info},
    {"BM", CommandType::laser_on},      {"QT", CommandType::laser_off},    {"RS", CommandType::reset},
    {"GD", CommandType::scan_3char},    {"GS", CommandType::scan_2char},   {"MD", CommandType::stream_3char},
    {"MS", CommandType::stream_2char},  {"TM", CommandType::time},         {"SS", CommandType::bit_rate},
    {"CR", CommandType::motor_speed},   {"HS", CommandType::sensitivity},  {"DB", CommandType::malfunction},
}};

bool is_tag_char(char c) {
  return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == ' ' || c == '.' ||
         c == '_' || c == '+' || c == '@';
}

// Reads `width` decimal digits at `pos`; names the field in `problem` when not.
bool read_digits(std::string_view params, std::size_t& pos, std::size_t width, std::string_view field,
                 int& value, std::string& problem) {
  if (pos + width > params.size()) {
    if (problem.empty()) problem = std::string(field) + " is missing (" + std::to_string(width) + " digits expected)";
    return false;
  }
  int result = 0;
  for (std::size_t i = 0; i < width; ++i) {
    const char c = params[pos + i];
    if (c < '0' || c > '9') {
      if (problem.empty()) {
        problem = std::string(field) + " '" + std::string(params.substr(pos, width)) + "' is not " +
                  std::to_string(width) + " decimal digits";
      }
      return false;
    }
    result = result * 10 + (c - '0');
  }
  value = result;
  pos += width;
  return true;
}

// Parses the fixed-width numeric parameters of each command type.
bool parse_parameters(std::string_view params, Command& out) {
  std::size_t pos = 0;
  bool ok = true;
  std::string& problem = out.problem;
  switch (out.type) {
    case CommandType::scan_3char:
    case CommandType::scan_2char:
    case CommandType::stream_3char:
    case CommandType::stream_2char:
      ok = read_digits(params, pos, 4, "start step", out.start_step, problem) &&
           read_digits(params, pos, 4, "end step", out.end_step, problem) &&
           read_digits(params, pos, 2, "cluster count", out.cluster, problem);
      if (ok && is_stream_command(out.type)) {
        ok = read_digits(params, pos, 1, "scan interval", out.scan_interval, problem) &&
             read_digits(params, pos, 2, "number of scans", out.scan_count, problem);
      }
      break;
    case CommandType::time:
      ok = read_digits(params, pos, 1, "TM mode", out.code, problem);
      if (ok && out.code > 2) {
        problem = "TM mode " + std::to_string(out.code) + " is not 0, 1 or 2";
        ok = false;
      }
      break;
    case CommandType::bit_rate: {
      int rate = 0;
      ok = read_digits(params, pos, 6, "bit rate", rate, problem);
      out.bit_rate = rate;
      break;
    }
    case CommandType::motor_speed: ok = read_digits(params, pos, 2, "motor speed level", out.code, problem); break;
    case CommandType::sensitivity: ok = read_digits(params, pos, 1, "sensitivity mode", out.code, problem); break;
    case CommandType::malfunction: ok = read_digits(params, pos, 2, "malfunction code", out.code, problem); break;
    default: break;
  }
  if (ok && pos != params.size()) {
    problem = "unexpected parameter characters '" + std::string(params.substr(pos)) + "'";
    ok = false;
  }
  return ok;
}

bool tag_problem(std::string_view tag, std::string& problem) {
  if (tag.size() > kMaxTagChars) {
    problem = "tag has " + std::to_string(tag.size()) + " characters, at most 16 allowed";
    return true;
  }
  for (std::size_t i = 0; i < tag.size(); ++i) {
    if (!is_tag_char(tag[i])) {
      problem = "tag character " + std::to_string(i) + " '" + std::string(1, tag[i]) +
                "' is not a letter, digit, space or . _ + @";
      return true;
    }
  }
  return false;
}

std::string with_tag(std::string command, std::string_view tag) {
  if (!tag.empty()) {
    validate_tag(tag);
    command += ';';
    command += tag;
  }
  command += '\n';
  return command;
}

void require_range(int value, int lowest, int highest, std::string_view field) {
  if (value < lowest || value > highest) {
    throw InputError("SCIP command: " + std::string(field) + " " + std::to_string(value) + " is outside " +
                     std::to_string(lowest) + ".." + std::to_string(highest));
  }
}

void append_digits(int value, int width, std::string& out) {
  std::string digits = std::to_string(value);
  out.append(static_cast<std::size_t>(width) - digits.size(), '0');
  out += digits;
}

std::string scan_prefix(const ScanRequest& request, std::string_view code) {
  require_range(request.start_step, 0, 9999, "start step");
  require_range(request.end_step, request.start_step, 9999, "end step");
  require_range(request.cluster, 0, 99, "cluster count");
  std::string text(code);
  append_digits(request.start_step, 4, text);
  append_digits(request.end_step, 4, text);
  append_digits(request.cluster, 2, text);
  return text;
}

}  // namespace

std::string_view command_code(CommandType type) {
  if (type == CommandType::switch_to_scip2) return kSwitchCode;
  for (const auto& entry : kCodes) {
    if (entry.type == type) return entry.code;
  }
  return "??";
}

int chars_per_value(CommandType type) {
  switch (type) {
    case CommandType::scan_3char:
    case CommandType::stream_3char: return 3;
    case CommandType::scan_2char:
    case CommandType::stream_2char: return 2;
    default: return 0;
  }
}

bool parse_command(std::string_view line, Command& out) {
  out.type = CommandType::unknown;
  out.text.assign(line);
  out.tag.clear();
  out.has_tag = false;
  out.well_formed = false;
  out.problem.clear();
  out.start_step = out.end_step = out.cluster = out.scan_interval = out.scan_count = out.code = 0;
  out.bit_rate = 0;
  for (const char c : line) {
    if (c < 0x20 || c > 0x7E) return false;
  }
  std::size_t code_length = 2;
  if (line.substr(0, kSwitchCode.size()) == kSwitchCode) {
    out.type = CommandType::switch_to_scip2;
    code_length = kSwitchCode.size();
  } else if (line.size() >= 2) {
    for (const auto& entry : kCodes) {
      if (line.substr(0, 2) == entry.code) out.type = entry.type;
    }
  }
  if (out.type == CommandType::unknown) return false;

  const std::size_t semicolon = line.find(';', code_length);
  const std::string_view params = line.substr(code_length, semicolon == std::string_view::npos
                                                               ? std::string_view::npos
                                                               : semicolon - code_length);
  if (semicolon != std::string_view::npos) {
    out.has_tag = true;
    out.tag.assign(line.substr(semicolon + 1));
  }
  out.well_formed = parse_parameters(params, out) && !tag_problem(out.tag, out.problem);
  return true;
}

Command parse_command(std::string_view line) {
  Command command;
  parse_command(line, command);
  return command;
}

int expected_value_count(const Command& command) {
  if (!is_distance_command(command.type) || command.end_step < command.start_step) return 0;
  const int steps = command.end_step - command.start_step + 1;
  const int cluster = command.cluster < 1 ? 1 : command.cluster;
  return (steps + cluster - 1) / cluster;
}

bool echo_matches(const Command& sent, const Command& echo) {
  if (sent.type != echo.type) return false;
  if (!is_stream_command(sent.type) || !sent.well_formed || !echo.well_formed) return sent.text == echo.text;
  return sent.start_step == echo.start_step && sent.end_step == echo.end_step && sent.cluster == echo.cluster &&
         sent.scan_interval == echo.scan_interval && sent.has_tag == echo.has_tag && sent.tag == echo.tag &&
         (sent.scan_count == 0 ? echo.scan_count == 0 : echo.scan_count <= sent.scan_count);
}

void validate_tag(std::string_view tag) {
  std::string problem;
  if (tag_problem(tag, problem)) throw InputError("SCIP command: " + problem);
}

std::string version_command(std::string_view tag) { return with_tag("VV", tag); }
std::string parameters_command(std::string_view tag) { return with_tag("PP", tag); }
std::string status_info_command(std::string_view tag) { return with_tag("II", tag); }
std::string laser_on_command(std::string_view tag) { return with_tag("BM", tag); }
std::string laser_off_command(std::string_view tag) { return with_tag("QT", tag); }
std::string reset_command(std::string_view tag) { return with_tag("RS", tag); }
std::string switch_to_scip2_command() { return std::string(kSwitchCode) + '\n'; }

std::string time_command(TimeMode mode, std::string_view tag) {
  const int code = static_cast<int>(mode);
  require_range(code, 0, 2, "TM mode");
  return with_tag("TM" + std::to_string(code), tag);
}

std::string single_scan_command(const ScanRequest& request, std::string_view tag) {
  return with_tag(scan_prefix(request, request.two_char_values ? "GS" : "GD"), tag);
}

std::string stream_command(const ScanRequest& request, int scan_interval, int scan_count, std::string_view tag) {
  std::string text = scan_prefix(request, request.two_char_values ? "MS" : "MD");
  require_range(scan_interval, 0, 9, "scan interval");
  require_range(scan_count, 0, 99, "number of scans");
  append_digits(scan_interval, 1, text);
  append_digits(scan_count, 2, text);
  return with_tag(std::move(text), tag);
}

}  // namespace stridemap::scip
