#pragma once
// The seam between the URG driver and whatever carries its bytes: a serial
// port (devices/serial_port.hpp: POSIX termios, the URG's USB CDC-ACM port), a
// pseudo-terminal, or an in-memory fake in tests. Every call waits at most
// its timeout, so a driver built on it can never hang its caller. A lost
// link is a result, not an exception: unplugging the sensor is an event the
// driver must survive.
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <string_view>

namespace stridemap {

enum class StreamStatus : std::uint8_t {
  ok,       ///< bytes moved (a read may return fewer than asked)
  timeout,  ///< nothing (more) could be moved within the timeout
  closed,   ///< the link is gone (hang-up, device unplugged, read or write error): reopen it
};

struct StreamResult {
  StreamStatus status = StreamStatus::ok;
  std::size_t bytes = 0;  ///< bytes read, or bytes written before the timeout or the loss
  std::string message;    ///< for `closed`: what the system said, naming the device
};

class ByteStream {
 public:
  virtual ~ByteStream() = default;
  /// Reads what is available, up to buffer.size() bytes, waiting at most
  /// `timeout` for the first byte. timeout 0 only takes what is there.
  virtual StreamResult read(std::span<char> buffer, std::chrono::milliseconds timeout) = 0;
  /// Writes all of `bytes` unless `timeout` passes or the link is lost first.
  virtual StreamResult write(std::string_view bytes, std::chrono::milliseconds timeout) = 0;
  /// Throws away bytes received and not read yet (stale data from before a
  /// reconnect or a stopped stream).
  virtual void discard_input() = 0;
  /// The device, for messages ("/dev/ttyACM0").
  virtual const std::string& name() const = 0;
};

/// Opens the link (again). Returns nullptr and sets `error` (naming the
/// device and the reason) when it cannot be opened now; the driver calls it
/// again later, so a missing device is not fatal.
using ByteStreamOpener = std::function<std::unique_ptr<ByteStream>(std::string& error)>;

}  // namespace stridemap
