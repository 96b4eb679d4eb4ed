#include "stridemap/devices/serial_port.hpp"

#include <fcntl.h>
#include <sys/ioctl.h>
#include <termios.h>
#include <unistd.h>

#include <cerrno>

#include "fd_stream.hpp"
#include "stridemap/core/error.hpp"

namespace stridemap::io {
namespace {

speed_t speed_of(int bit_rate) {
  switch (bit_rate) {
    case 19200: return B19200;
    case 38400: return B38400;
    case 57600: return B57600;
    case 115200: return B115200;
    case 230400: return B230400;
    case 460800: return B460800;
    case 921600: return B921600;
    default: break;
  }
  throw InputError("serial port: bit rate " + std::to_string(bit_rate) +
                   " is not supported; use 19200, 38400, 57600, 115200, 230400, 460800 or 921600");
}

}  // namespace

std::unique_ptr<SerialPort> SerialPort::open(const std::string& path, const SerialPortOptions& options,
                                             std::string& error) {
  const speed_t speed = speed_of(options.bit_rate);
  const int fd = ::open(path.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) {
    error = detail::system_message("cannot open", path, errno);
    return nullptr;
  }
  std::unique_ptr<SerialPort> port(new SerialPort(fd, path));
  termios tio{};
  if (!::isatty(fd) || ::tcgetattr(fd, &tio) != 0) {
    error = path + " is not a serial device (not a terminal)";
    return nullptr;
  }
  if (options.exclusive && ::ioctl(fd, TIOCEXCL) != 0) {
    error = detail::system_message("cannot get exclusive access to", path, errno);
    return nullptr;
  }
  ::cfmakeraw(&tio);
  tio.c_cflag |= CLOCAL | CREAD;
  tio.c_cc[VMIN] = 0;
  tio.c_cc[VTIME] = 0;
  ::cfsetispeed(&tio, speed);
  ::cfsetospeed(&tio, speed);
  if (::tcsetattr(fd, TCSANOW, &tio) != 0) {
    error = detail::system_message("cannot configure", path, errno);
    return nullptr;
  }
  ::tcflush(fd, TCIOFLUSH);
  return port;
}

ByteStreamOpener SerialPort::opener(const std::string& path, const SerialPortOptions& options) {
  speed_of(options.bit_rate);  // a bad rate is the caller's error, reported now
  return [path, options](std::string& error) -> std::unique_ptr<ByteStream> { return open(path, options, error); };
}

SerialPort::~SerialPort() {
  if (fd_ < 0) return;
  // The exclusive flag belongs to the terminal, not to this descriptor: clear
  // it so that the next open (ours, after a reconnect) is not refused.
  ::ioctl(fd_, TIOCNXCL);
  ::close(fd_);
}

StreamResult SerialPort::read(std::span<char> buffer, std::chrono::milliseconds timeout) {
  return detail::read_fd(fd_, buffer, timeout, path_);
}

StreamResult SerialPort::write(std::string_view bytes, std::chrono::milliseconds timeout) {
  return detail::write_fd(fd_, bytes, timeout, path_);
}

void SerialPort::discard_input() { ::tcflush(fd_, TCIFLUSH); }

}  // namespace stridemap::io
