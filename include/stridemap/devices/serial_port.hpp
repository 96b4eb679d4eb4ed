#pragma once
// A serial device as a ByteStream (POSIX termios): the URG-04LX's USB port is
// a CDC-ACM device (/dev/ttyACM0), where the bit rate is ignored; on an
// RS-232 adapter it matters. Raw mode (no echo, no line editing, no CR/LF
// translation), non-blocking, and every read and write bounded by its
// timeout. Also works on a pseudo-terminal (the emulator's link).
#include <memory>
#include <string>

#include "stridemap/sensors/byte_stream.hpp"

namespace stridemap::io {

struct SerialPortOptions {
  /// Bit rate for a real serial line: 19200, 38400, 57600, 115200, 230400,
  /// 460800 or 921600. Ignored by CDC-ACM and pseudo-terminals.
  int bit_rate = 115200;
  /// Refuse a second open of the same device (TIOCEXCL) while it is open.
  bool exclusive = true;
};

class SerialPort final : public ByteStream {
 public:
  /// Opens `path` (following symlinks), sets raw mode and drops stale input.
  /// Returns nullptr and sets `error` when the path does not exist, cannot be
  /// opened, or is not a terminal ("... is not a serial device"). Throws
  /// InputError for an unsupported bit rate (a caller's mistake, not the
  /// device's).
  static std::unique_ptr<SerialPort> open(const std::string& path, const SerialPortOptions& options,
                                          std::string& error);
  /// An opener for the driver that reopens `path` on every call.
  static ByteStreamOpener opener(const std::string& path, const SerialPortOptions& options = {});

  ~SerialPort() override;
  SerialPort(const SerialPort&) = delete;
  SerialPort& operator=(const SerialPort&) = delete;

  StreamResult read(std::span<char> buffer, std::chrono::milliseconds timeout) override;
  StreamResult write(std::string_view bytes, std::chrono::milliseconds timeout) override;
  void discard_input() override;
  const std::string& name() const override { return path_; }

 private:
  SerialPort(int fd, std::string path) : fd_(fd), path_(std::move(path)) {}
  int fd_ = -1;
  std::string path_;
};

}  // namespace stridemap::io
