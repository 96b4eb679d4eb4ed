#include "stridemap/sensors/scip_status.hpp"

#include "scip_line_grammar.hpp"

namespace stridemap::scip {

namespace {

// Status as a number when both characters are decimal digits, else -1.
int decimal_status(std::string_view status) {
  if (status.size() != 2 || status[0] < '0' || status[0] > '9' || status[1] < '0' || status[1] > '9') return -1;
  return (status[0] - '0') * 10 + (status[1] - '0');
}

bool is_generic_error(std::string_view status) {
  return status.size() == 2 && status[0] == '0' && status[1] >= 'A' && status[1] <= 'I';
}

std::string_view generic_meaning(char second) {
  switch (second) {
    case 'A': return "cannot create the reply internally";
    case 'B': return "buffer shortage or command already being processed";
    case 'C': return "insufficient parameters (1)";
    case 'D': return "undefined command (1)";
    case 'E': return "undefined command (2)";
    case 'F': return "insufficient parameters (2)";
    case 'G': return "string longer than 16 characters";
    case 'H': return "invalid characters in the string";
    case 'I': return "firmware update mode";
    default: return "unknown status";
  }
}

// The decimal codes each command defines besides "00".
bool is_command_specific(CommandType command, int code) {
  switch (command) {
    case CommandType::laser_on: return code >= 1 && code <= 2;
    case CommandType::scan_3char:
    case CommandType::scan_2char: return (code >= 1 && code <= 5) || code == 10 || (code >= 50 && code <= 98);
    case CommandType::stream_3char:
    case CommandType::stream_2char: return (code >= 1 && code <= 7) || (code >= 21 && code <= 99);
    case CommandType::time:
    case CommandType::bit_rate:
    case CommandType::motor_speed: return code >= 1 && code <= 4;
    case CommandType::sensitivity: return code >= 1 && code <= 3;
    case CommandType::malfunction: return code >= 1 && code <= 5;
    default: return false;
  }
}

std::string_view scan_meaning(int code) {
  switch (code) {
    case 1: return "start step is not numeric";
    case 2: return "end step is not numeric";
    case 3: return "cluster count is not numeric";
    case 4: return "end step out of range";
    case 5: return "end step smaller than start step";
    case 6: return "scan interval is not numeric";
    case 7: return "number of scans is not numeric";
    case 10: return "laser is off";
    case 98: return "resumed after the error was cleared";
    case 99: return "data frame";
    default: break;
  }
  if (code >= 21 && code <= 49) return "measurement stopped to verify an error";
  if (code >= 50 && code <= 97) return "hardware trouble (laser or motor)";
  return "unknown status";
}

std::string_view setting_meaning(CommandType command, int code) {
  switch (code) {
    case 1: return command == CommandType::time ? "invalid TM mode" : "invalid parameter";
    case 2:
      if (command == CommandType::time) return "adjust mode already on";
      if (command == CommandType::sensitivity) return "already in that mode";
      return "parameter out of range";
    case 3:
      if (command == CommandType::time) return "adjust mode already off";
      if (command == CommandType::sensitivity) return "not supported";
      return "already set";
    case 4: return command == CommandType::time ? "TM1 while not in adjust mode" : "not supported";
    case 5: return "simulated malfunction";
    default: return "unknown status";
  }
}

}  // namespace

bool is_known_status(CommandType command, std::string_view status) {
  if (status.size() == 1) return detail::is_status_char(status[0]);
  if (status == "00" || is_generic_error(status)) return true;
  const int code = decimal_status(status);
  return code > 0 && is_command_specific(command, code);
}

std::string_view status_meaning(CommandType command, std::string_view status) {
  if (status.size() == 1) return status[0] == '0' ? "SCIP 1.1 OK" : "SCIP 1.1 error";
  if (status == "00") return "OK";
  if (is_generic_error(status)) return generic_meaning(status[1]);
  const int code = decimal_status(status);
  if (code <= 0 || !is_command_specific(command, code)) return "unknown status";
  switch (command) {
    case CommandType::laser_on: return code == 1 ? "laser malfunction" : "laser already on";
    case CommandType::scan_3char:
    case CommandType::scan_2char: return code == 98 ? "hardware trouble (laser or motor)" : scan_meaning(code);
    case CommandType::stream_3char:
    case CommandType::stream_2char: return scan_meaning(code);
    default: return setting_meaning(command, code);
  }
}

bool status_means_success(CommandType command, std::string_view status) {
  if (command == CommandType::switch_to_scip2) return status == "0" || status == "0E" || status == "00";
  if (status == "00") return true;
  switch (command) {
    case CommandType::stream_3char:
    case CommandType::stream_2char: return status == "99";
    case CommandType::laser_on: return status == "02";
    case CommandType::time: return status == "02" || status == "03";
    case CommandType::bit_rate:
    case CommandType::motor_speed: return status == "03";
    case CommandType::sensitivity: return status == "02";
    default: return false;
  }
}

}  // namespace stridemap::scip
