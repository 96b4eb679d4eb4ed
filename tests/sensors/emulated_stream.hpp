#pragma once
// The URG emulator behind the driver's ByteStream interface, in memory and
// on a virtual clock: the driver's timeouts advance the clock instead of
// waiting, so a test of minutes of sensor time runs in milliseconds and the
// same test always sees the same bytes. Hooks let a test damage, drop or
// hold back what the sensor sends, and make the device vanish.
#include <algorithm>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "stridemap/sensors/byte_stream.hpp"
#include "stridemap/sim/urg_emulator.hpp"

namespace stridemap::test {

/// Virtual time in milliseconds, shared by the fake device and the driver.
struct VirtualClock {
  std::int64_t now_ms = 0;
  double seconds() const { return static_cast<double>(now_ms) / 1000.0; }
};

/// A device: an emulator plus what the "wire" does to its output.
struct EmulatedDevice {
  EmulatedDevice(const UrgEmulatorOptions& options, UrgScanSource& source, VirtualClock& clock)
      : emulator(options, source, clock.now_ms), clock(clock) {}

  UrgEmulator emulator;
  VirtualClock& clock;
  bool present = true;    ///< false: opening fails, an open stream reports `closed`
  bool silent = false;    ///< true: reads nothing and sends nothing (a stalled sensor)
  std::uint64_t opens = 0;
  /// Called for every output chunk; may change `bytes` (empty: nothing sent).
  std::function<void(EmulatorOutput&)> on_output;
  std::string wire;       ///< bytes sent and not read yet
  std::vector<EmulatorOutput> sent_scans;  ///< scans as they went on the wire (after on_output)
  std::string garbage_on_open;  ///< bytes waiting in the port when it is opened
  std::string answer_with;      ///< not empty: a device that is no URG answers every write with this

  void pump() {
    if (silent) return;
    emulator.advance(clock.now_ms);
    for (EmulatorOutput& out : emulator.output()) {
      if (on_output) on_output(out);
      if (out.is_scan && !out.bytes.empty()) sent_scans.push_back(out);
      wire += out.bytes;
    }
    emulator.output().clear();
  }
};

class EmulatedStream final : public ByteStream {
 public:
  explicit EmulatedStream(EmulatedDevice& device) : device_(device), generation_(device.opens) {}

  StreamResult read(std::span<char> buffer, std::chrono::milliseconds timeout) override {
    if (!alive()) return {StreamStatus::closed, 0, name_ + ": the device hung up (unplugged?)"};
    device_.pump();
    if (device_.wire.empty() && !device_.silent) {
      // Sleep until the next scan is due or the timeout passes.
      const std::int64_t due = device_.emulator.next_due_ms();
      const std::int64_t until = std::min<std::int64_t>(device_.clock.now_ms + timeout.count(), due);
      device_.clock.now_ms = std::max(device_.clock.now_ms, until);
      device_.pump();
    } else if (device_.wire.empty()) {
      device_.clock.now_ms += timeout.count();
    }
    if (device_.wire.empty()) return {StreamStatus::timeout, 0, {}};
    const std::size_t n = std::min(buffer.size(), device_.wire.size());
    std::copy_n(device_.wire.begin(), n, buffer.begin());
    device_.wire.erase(0, n);
    return {StreamStatus::ok, n, {}};
  }

  StreamResult write(std::string_view bytes, std::chrono::milliseconds) override {
    if (!alive()) return {StreamStatus::closed, 0, name_ + ": the device hung up (unplugged?)"};
    if (!device_.answer_with.empty()) {
      device_.wire += device_.answer_with;
    } else if (!device_.silent) {
      device_.pump();
      device_.emulator.receive(bytes, device_.clock.now_ms);
      device_.pump();
    }
    return {StreamStatus::ok, bytes.size(), {}};
  }

  void discard_input() override { device_.wire.clear(); }
  const std::string& name() const override { return name_; }

 private:
  bool alive() const { return device_.present && device_.opens == generation_; }
  EmulatedDevice& device_;
  std::uint64_t generation_;
  std::string name_ = "/dev/fake-urg";
};

/// An opener for the driver; fails while the device is absent.
inline ByteStreamOpener emulated_opener(EmulatedDevice& device) {
  return [&device](std::string& error) -> std::unique_ptr<ByteStream> {
    if (!device.present) {
      error = "cannot open /dev/fake-urg: No such file or directory";
      return nullptr;
    }
    ++device.opens;
    device.wire = device.garbage_on_open;
    return std::make_unique<EmulatedStream>(device);
  };
}

}  // namespace stridemap::test
