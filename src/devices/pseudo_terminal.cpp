#include "stridemap/devices/pseudo_terminal.hpp"

#include <fcntl.h>
#include <stdlib.h>
#include <sys/ioctl.h>
#include <sys/stat.h>
#include <termios.h>
#include <unistd.h>

#include <cerrno>

#include "fd_stream.hpp"
#include "stridemap/core/error.hpp"

namespace stridemap::io {
namespace {

[[noreturn]] void fail(const std::string& what, const std::string& path, int error_number) {
  throw InputError(detail::system_message(what, path, error_number));
}

}  // namespace

PseudoTerminal::PseudoTerminal(const std::string& link_path) : link_path_(link_path) {
  master_fd_ = ::posix_openpt(O_RDWR | O_NOCTTY | O_CLOEXEC);
  if (master_fd_ < 0) fail("cannot open a pseudo-terminal (/dev/ptmx) for", link_path, errno);
  try {
    if (::grantpt(master_fd_) != 0 || ::unlockpt(master_fd_) != 0) fail("cannot unlock the pseudo-terminal for", link_path, errno);
    char name[128];
    if (::ptsname_r(master_fd_, name, sizeof name) != 0) fail("cannot name the pseudo-terminal for", link_path, errno);
    client_path_ = name;
    const int flags = ::fcntl(master_fd_, F_GETFL);
    ::fcntl(master_fd_, F_SETFL, flags | O_NONBLOCK);
    client_hold_fd_ = ::open(client_path_.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
    if (client_hold_fd_ < 0) fail("cannot open", client_path_, errno);
    // Raw before anyone can connect: no echo of the host's commands, no CR/LF games.
    termios tio{};
    ::tcgetattr(client_hold_fd_, &tio);
    ::cfmakeraw(&tio);
    ::tcsetattr(client_hold_fd_, TCSANOW, &tio);

    struct stat st{};
    if (::lstat(link_path.c_str(), &st) == 0) {
      if (!S_ISLNK(st.st_mode)) {
        throw InputError(link_path + ": exists and is not a symlink; the emulator will not replace it");
      }
      if (::unlink(link_path.c_str()) != 0) fail("cannot replace the old symlink", link_path, errno);
    }
    if (::symlink(client_path_.c_str(), link_path.c_str()) != 0) fail("cannot create the symlink", link_path, errno);
  } catch (...) {
    if (client_hold_fd_ >= 0) ::close(client_hold_fd_);
    ::close(master_fd_);
    throw;
  }
}

PseudoTerminal::~PseudoTerminal() {
  // Remove the link only if it still points at this pty (a new emulator may own it now).
  char target[256];
  const ssize_t n = ::readlink(link_path_.c_str(), target, sizeof target - 1);
  if (n > 0 && std::string(target, static_cast<std::size_t>(n)) == client_path_) ::unlink(link_path_.c_str());
  if (client_hold_fd_ >= 0) ::close(client_hold_fd_);
  if (master_fd_ >= 0) ::close(master_fd_);
}

StreamResult PseudoTerminal::read(std::span<char> buffer, std::chrono::milliseconds timeout) {
  return detail::read_fd(master_fd_, buffer, timeout, link_path_);
}

StreamResult PseudoTerminal::write(std::string_view bytes, std::chrono::milliseconds timeout) {
  return detail::write_fd(master_fd_, bytes, timeout, link_path_);
}

void PseudoTerminal::discard_input() { ::tcflush(master_fd_, TCIFLUSH); }

std::size_t PseudoTerminal::unread_by_client() const {
  int queued = 0;
  if (::ioctl(client_hold_fd_, FIONREAD, &queued) != 0 || queued < 0) return 0;
  return static_cast<std::size_t>(queued);
}

}  // namespace stridemap::io
