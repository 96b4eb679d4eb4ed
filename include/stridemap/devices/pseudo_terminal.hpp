#pragma once
// The device end of a pseudo-terminal, for the URG emulator: posix_openpt,
// raw mode, and a symlink at a path of the user's choice that a driver opens
// like /dev/ttyACM0. The emulator writes and reads the master side through
// the ByteStream interface. Closing it (destructor or close()) makes the
// link vanish, as an unplugged sensor does: the client's reads fail with a
// hang-up and the symlink is removed.
#include <memory>
#include <string>

#include "stridemap/sensors/byte_stream.hpp"

namespace stridemap::io {

class PseudoTerminal final : public ByteStream {
 public:
  /// Opens a new pty and points `link_path` at its client side (replacing a
  /// symlink left there, e.g. by a killed emulator). Throws InputError naming
  /// the path when the pty cannot be created, or `link_path` exists and is not
  /// a symlink, or the symlink cannot be made.
  explicit PseudoTerminal(const std::string& link_path);
  ~PseudoTerminal() override;
  PseudoTerminal(const PseudoTerminal&) = delete;
  PseudoTerminal& operator=(const PseudoTerminal&) = delete;

  /// The client side, e.g. /dev/pts/3.
  const std::string& client_path() const { return client_path_; }
  const std::string& link_path() const { return link_path_; }

  StreamResult read(std::span<char> buffer, std::chrono::milliseconds timeout) override;
  StreamResult write(std::string_view bytes, std::chrono::milliseconds timeout) override;
  void discard_input() override;
  const std::string& name() const override { return link_path_; }

  /// Bytes written to the client and not read by it yet (TIOCOUTQ on the
  /// client side), so the emulator can see a client that does not read.
  std::size_t unread_by_client() const;

 private:
  int master_fd_ = -1;
  int client_hold_fd_ = -1;  // kept open so the pty survives clients closing and reopening
  std::string client_path_;
  std::string link_path_;
};

}  // namespace stridemap::io
