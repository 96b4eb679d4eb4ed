// The serial transport on a pseudo-terminal (the emulator's link): bytes
// both ways unchanged, every call bounded by its timeout, a hang-up seen as
// a lost link, and clear errors for paths that are no serial device.
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <string>

#include "live/test_folder.hpp"
#include "stridemap/core/error.hpp"
#include "stridemap/devices/pseudo_terminal.hpp"
#include "stridemap/devices/serial_port.hpp"

namespace stridemap::io {
namespace {

using std::chrono::milliseconds;

std::string read_all(ByteStream& stream, std::size_t bytes) {
  std::string out;
  char buffer[256];
  while (out.size() < bytes) {
    const StreamResult r = stream.read(buffer, milliseconds(2000));
    if (r.status != StreamStatus::ok) break;
    out.append(buffer, r.bytes);
  }
  return out;
}

TEST(SerialPort, PseudoTerminalCarriesRawBytesBothWays) {
  test::TestFolder dir;
  PseudoTerminal pty(dir / "urg");
  EXPECT_TRUE(std::filesystem::is_symlink(dir / "urg"));
  std::string error;
  auto port = SerialPort::open(dir / "urg", {}, error);
  ASSERT_TRUE(port) << error;
  const std::string command = "MD0044072501000\r\nQT\n";  // CR must not turn into LF or vanish
  ASSERT_EQ(port->write(command, milliseconds(1000)).status, StreamStatus::ok);
  EXPECT_EQ(read_all(pty, command.size()), command);
  std::string reply;
  for (int i = 0; i < 256; ++i) reply += static_cast<char>(i);
  ASSERT_EQ(pty.write(reply, milliseconds(1000)).status, StreamStatus::ok);
  EXPECT_EQ(read_all(*port, reply.size()), reply);
}

TEST(SerialPort, ReadTimesOutWithinItsTimeout) {
  test::TestFolder dir;
  PseudoTerminal pty(dir / "urg");
  std::string error;
  auto port = SerialPort::open(dir / "urg", {}, error);
  ASSERT_TRUE(port) << error;
  char buffer[16];
  const auto start = std::chrono::steady_clock::now();
  const StreamResult r = port->read(buffer, milliseconds(50));
  const auto took = std::chrono::steady_clock::now() - start;
  EXPECT_EQ(r.status, StreamStatus::timeout);
  EXPECT_GE(took, milliseconds(45));
  EXPECT_LT(took, milliseconds(1000));
  EXPECT_EQ(port->read(buffer, milliseconds(0)).status, StreamStatus::timeout);
}

TEST(SerialPort, VanishingLinkIsReportedAsClosedAndTheSymlinkGoes) {
  test::TestFolder dir;
  auto pty = std::make_unique<PseudoTerminal>(dir / "urg");
  std::string error;
  auto port = SerialPort::open(dir / "urg", {}, error);
  ASSERT_TRUE(port) << error;
  pty.reset();  // unplugged
  EXPECT_FALSE(std::filesystem::exists(std::filesystem::symlink_status(dir / "urg")));
  char buffer[16];
  const StreamResult r = port->read(buffer, milliseconds(1000));
  EXPECT_EQ(r.status, StreamStatus::closed);
  EXPECT_FALSE(r.message.empty());
  EXPECT_FALSE(SerialPort::open(dir / "urg", {}, error));
  EXPECT_NE(error.find("No such file or directory"), std::string::npos) << error;
  // It comes back under the same name; a new open works.
  PseudoTerminal again(dir / "urg");
  EXPECT_TRUE(SerialPort::open(dir / "urg", {}, error)) << error;
}

TEST(SerialPort, PathsThatAreNoSerialDeviceAreNamed) {
  test::TestFolder dir;
  std::string error;
  EXPECT_FALSE(SerialPort::open(dir / "nothing", {}, error));
  EXPECT_EQ(error, "cannot open " + dir / "nothing" + ": No such file or directory");
  EXPECT_FALSE(SerialPort::open(dir.write("file.txt", "x"), {}, error));
  EXPECT_EQ(error, dir / "file.txt" + " is not a serial device (not a terminal)");
  SerialPortOptions options;
  options.bit_rate = 12345;
  EXPECT_THROW(SerialPort::open(dir / "nothing", options, error), InputError);
  dir.write("taken", "x");
  EXPECT_THROW(PseudoTerminal(dir / "taken"), InputError);  // not a symlink: never replaced
}

}  // namespace
}  // namespace stridemap::io
