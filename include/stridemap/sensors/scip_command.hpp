#pragma once
// SCIP 2.0 commands as the host sends them and as the sensor echoes them back:
// encoders that build the exact bytes (ending in LF) and a parser that turns a
// command or echo line into its type and parameters (used by the decoder for
// echoes and by an emulator for the host's commands). Pure code, no I/O.
#include <cstdint>
#include <string>
#include <string_view>

namespace stridemap::scip {

/// The commands a URG-04LX understands (SCIP 2.0, plus the SCIP2.0 switch).
enum class CommandType : std::uint8_t {
  unknown,
  version,        ///< VV: vendor, product, firmware, protocol, serial
  parameters,     ///< PP: model, distance and step limits, motor speed
  status_info,    ///< II: laser, motor, mode, bit rate, time, state
  laser_on,       ///< BM
  laser_off,      ///< QT (also stops MD/MS)
  reset,          ///< RS (laser off, defaults, timer reset)
  scan_3char,     ///< GD: one scan, 3-character values
  scan_2char,     ///< GS: one scan, 2-character values (max 4095 mm)
  stream_3char,   ///< MD: continuous scans, 3-character values
  stream_2char,   ///< MS: continuous scans, 2-character values
  time,           ///< TM0 / TM1 / TM2
  bit_rate,       ///< SSnnnnnn
  motor_speed,    ///< CRnn
  sensitivity,    ///< HSn
  malfunction,    ///< DBnn (simulated malfunction)
  switch_to_scip2 ///< SCIP2.0
};

/// Two-letter code ("VV", "GD", ...) or "SCIP2.0"; "??" for unknown.
std::string_view command_code(CommandType type);

/// True for GD/GS/MD/MS.
constexpr bool is_distance_command(CommandType type) {
  return type == CommandType::scan_3char || type == CommandType::scan_2char ||
         type == CommandType::stream_3char || type == CommandType::stream_2char;
}
/// True for MD/MS.
constexpr bool is_stream_command(CommandType type) {
  return type == CommandType::stream_3char || type == CommandType::stream_2char;
}
/// Characters per distance value: 3 for GD/MD, 2 for GS/MS, 0 otherwise.
int chars_per_value(CommandType type);

/// TM sub-commands.
enum class TimeMode : std::uint8_t { adjust_on = 0, read = 1, adjust_off = 2 };

/// A parsed command or echo line (without its LF).
struct Command {
  CommandType type = CommandType::unknown;
  std::string text;     ///< the whole line as received, including ";tag"
  std::string tag;      ///< characters after ';' (empty when none)
  bool has_tag = false; ///< a ';' was present (the tag may still be empty)
  /// Parameters present, numeric where required, and the tag made of allowed
  /// characters with at most 16 of them. When false, `problem` says why; the
  /// sensor answers such commands with an error status, echoing them as sent.
  bool well_formed = false;
  std::string problem;
  int start_step = 0;     ///< GD/GS/MD/MS
  int end_step = 0;       ///< GD/GS/MD/MS
  int cluster = 0;        ///< GD/GS/MD/MS, as sent (00 behaves as 01)
  int scan_interval = 0;  ///< MD/MS: scans skipped between transmitted scans
  int scan_count = 0;     ///< MD/MS: scans requested (00 = until QT); in an echo: scans remaining
  int code = 0;           ///< TM mode, CR level, HS mode or DB code
  std::int32_t bit_rate = 0;  ///< SS
};

/// Parses one line (no LF; a trailing CR is not accepted). Returns false and
/// sets type = unknown if the line is not a known command (or holds bytes
/// outside printable ASCII). Otherwise fills `out` and returns true, with
/// out.well_formed telling whether its parameters are valid. Reuses out's storage.
bool parse_command(std::string_view line, Command& out);
Command parse_command(std::string_view line);

/// Number of distance values a GD/GS/MD/MS reply carries:
/// ceil((end - start + 1) / max(cluster, 1)); 0 when end < start.
int expected_value_count(const Command& command);

/// True when `echo` is the sensor's echo of `sent`: same line, except that MD/MS
/// data frames carry the number of scans remaining instead of the number asked.
bool echo_matches(const Command& sent, const Command& echo);

/// Checks a tag: at most 16 characters from letters, digits, space and ". _ + @".
/// Throws InputError naming the offending character.
void validate_tag(std::string_view tag);

// Encoders: each returns the exact bytes to send, ending in LF; `tag` (optional)
// is appended after ';' and comes back in the echo. Throw InputError naming
// the field when a parameter is out of range.
std::string version_command(std::string_view tag = {});      ///< VV
std::string parameters_command(std::string_view tag = {});   ///< PP
std::string status_info_command(std::string_view tag = {});  ///< II
std::string laser_on_command(std::string_view tag = {});     ///< BM
std::string laser_off_command(std::string_view tag = {});    ///< QT
std::string reset_command(std::string_view tag = {});        ///< RS
std::string time_command(TimeMode mode, std::string_view tag = {});  ///< TM0/1/2
std::string switch_to_scip2_command();                        ///< SCIP2.0

/// Step range and cluster of a GD/GS/MD/MS request.
struct ScanRequest {
  int start_step = 44;   ///< first step, 0..9999 (URG-04LX: AMIN = 44)
  int end_step = 725;    ///< last step, start_step..9999 (URG-04LX: AMAX = 725)
  int cluster = 1;       ///< adjacent steps merged into one value, 0..99 (0 acts as 1)
  bool two_char_values = false;  ///< GS/MS (max 4095 mm) instead of GD/MD
};

/// GD (or GS) one-scan request.
std::string single_scan_command(const ScanRequest& request, std::string_view tag = {});
/// MD (or MS) request: scan_interval 0..9 scans skipped between transmitted
/// ones, scan_count 0..99 scans (0 = until QT).
std::string stream_command(const ScanRequest& request, int scan_interval, int scan_count,
                           std::string_view tag = {});

}  // namespace stridemap::scip
