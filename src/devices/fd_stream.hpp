#pragma once
// Reading and writing a non-blocking file descriptor with a deadline, shared
// by the serial port and the pseudo-terminal (both terminals, both polled).
#include <chrono>
#include <span>
#include <string>
#include <string_view>

#include "stridemap/sensors/byte_stream.hpp"

namespace stridemap::io::detail {

/// poll() + read(): what is there, waiting at most `timeout` for the first
/// byte. A hang-up, EOF or I/O error is `closed` with a message naming `name`.
StreamResult read_fd(int fd, std::span<char> buffer, std::chrono::milliseconds timeout, const std::string& name);
/// poll() + write() until everything is written or `timeout` passes.
StreamResult write_fd(int fd, std::string_view bytes, std::chrono::milliseconds timeout, const std::string& name);
/// "<what> <name>: <strerror(errno)>".
std::string system_message(const std::string& what, const std::string& name, int error_number);

}  // namespace stridemap::io::detail
