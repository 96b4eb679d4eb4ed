#include "fd_stream.hpp"

#include <poll.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace stridemap::io::detail {
namespace {

using Clock = std::chrono::steady_clock;

int remaining_ms(Clock::time_point deadline) {
  const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now()).count();
  return left > 0 ? static_cast<int>(left) : 0;
}

StreamResult closed(std::size_t bytes, std::string message) {
  return {StreamStatus::closed, bytes, std::move(message)};
}

}  // namespace

std::string system_message(const std::string& what, const std::string& name, int error_number) {
  return what + " " + name + ": " + std::strerror(error_number);
}

StreamResult read_fd(int fd, std::span<char> buffer, std::chrono::milliseconds timeout, const std::string& name) {
  if (buffer.empty()) return {StreamStatus::ok, 0, {}};
  const Clock::time_point deadline = Clock::now() + timeout;
  // A terminal in raw mode with VMIN = VTIME = 0 returns 0 when it has no
  // data, so 0 means end of file only right after poll() said "readable".
  bool polled_readable = false;
  while (true) {
    const ssize_t got = ::read(fd, buffer.data(), buffer.size());
    if (got > 0) return {StreamStatus::ok, static_cast<std::size_t>(got), {}};
    if (got == 0 && polled_readable) return closed(0, name + ": end of file (the device hung up)");
    if (got < 0) {
      if (errno == EINTR) continue;
      if (errno != EAGAIN && errno != EWOULDBLOCK) return closed(0, system_message("cannot read", name, errno));
    }
    pollfd p{fd, POLLIN, 0};
    const int ready = ::poll(&p, 1, remaining_ms(deadline));
    if (ready < 0) {
      if (errno == EINTR) continue;
      return closed(0, system_message("cannot poll", name, errno));
    }
    if (ready == 0) return {StreamStatus::timeout, 0, {}};
    if ((p.revents & POLLIN) == 0 && (p.revents & (POLLHUP | POLLERR | POLLNVAL)) != 0) {
      return closed(0, name + ": the device hung up (unplugged?)");
    }
    polled_readable = true;  // POLLIN, possibly with POLLHUP: read what is left before reporting the loss
  }
}

StreamResult write_fd(int fd, std::string_view bytes, std::chrono::milliseconds timeout, const std::string& name) {
  const Clock::time_point deadline = Clock::now() + timeout;
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t put = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (put > 0) {
      done += static_cast<std::size_t>(put);
      continue;
    }
    if (put < 0 && errno == EINTR) continue;
    if (put < 0 && errno != EAGAIN && errno != EWOULDBLOCK) {
      return closed(done, system_message("cannot write to", name, errno));
    }
    pollfd p{fd, POLLOUT, 0};
    const int ready = ::poll(&p, 1, remaining_ms(deadline));
    if (ready < 0) {
      if (errno == EINTR) continue;
      return closed(done, system_message("cannot poll", name, errno));
    }
    if (ready == 0) return {StreamStatus::timeout, done, {}};
    if ((p.revents & (POLLHUP | POLLERR | POLLNVAL)) != 0 && (p.revents & POLLOUT) == 0) {
      return closed(done, name + ": the device hung up (unplugged?)");
    }
  }
  return {StreamStatus::ok, done, {}};
}

}  // namespace stridemap::io::detail
