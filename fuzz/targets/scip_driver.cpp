// The URG driver (sensors/urg_driver.hpp) against an emulated URG-04LX
// behind a fake ByteStream on a virtual clock, with the input as the script
// of a flaky link: each read delivers a chunk of the sensor's bytes whose
// size the input picks, or corrupts, drops or invents bytes, times out,
// fails (the cable pulled), power-cycles the sensor or makes the device
// vanish for a while; each write succeeds, times out or fails. When the
// script ends, the link turns perfect. What must hold:
//  - nothing escapes next(), and each call returns within its timeout plus
//    one write timeout of virtual time: the driver never hangs its caller;
//  - memory stays bounded (under ASan, where the allocator can be asked);
//  - delivered scans are numbered 0, 1, 2..., carry the requested steps and
//    finite times;
//  - once the link is perfect again, the driver is streaming scans within
//    20 s: it recovers from anything the script did.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <string>

#include "fuzz_input.hpp"
#include "fuzz_target.hpp"
#include "stridemap/core/error.hpp"
#include "stridemap/sensors/urg_driver.hpp"
#include "stridemap/sim/urg_emulator.hpp"

#if defined(__has_feature)
#if __has_feature(address_sanitizer)
#define STRIDEMAP_FUZZ_HEAP_COUNTER 1
#endif
#endif
#if defined(__SANITIZE_ADDRESS__)
#define STRIDEMAP_FUZZ_HEAP_COUNTER 1
#endif
#ifdef STRIDEMAP_FUZZ_HEAP_COUNTER
#include <sanitizer/allocator_interface.h>
#endif

namespace {

using namespace stridemap;
using fuzz::check;

std::size_t heap_in_use() {
#ifdef STRIDEMAP_FUZZ_HEAP_COUNTER
  return __sanitizer_get_current_allocated_bytes();
#else
  return 0;
#endif
}

class Counting final : public UrgScanSource {
 public:
  void scan(std::uint64_t index, double, std::vector<std::uint32_t>& values) override {
    values.assign(682, static_cast<std::uint32_t>(20 + index % 4000));
  }
};

// The sensor, the wire and the script; shared by every stream the opener makes.
struct Device {
  Device(fuzz::ByteReader& script, const UrgEmulatorOptions& options)
      : script(script), emulator(options, source, 0) {}

  fuzz::ByteReader& script;
  Counting source;
  UrgEmulator emulator;
  std::int64_t now_ms = 0;
  std::int64_t absent_until_ms = 0;
  std::uint64_t generation = 0;  // a stream of an older generation is closed
  std::string wire;              // sent by the sensor, not read yet

  bool perfect() const { return script.empty(); }
  void pump() {
    emulator.advance(now_ms);
    for (const EmulatorOutput& out : emulator.output()) wire += out.bytes;
    emulator.output().clear();
  }
};

class FakeStream final : public ByteStream {
 public:
  explicit FakeStream(Device& device) : device_(device), generation_(device.generation) {}

  StreamResult read(std::span<char> buffer, std::chrono::milliseconds timeout) override {
    if (generation_ != device_.generation) return closed();
    Device& d = device_;
    std::size_t limit = buffer.size();
    if (!d.perfect()) {
      fuzz::ByteReader& in = d.script;
      switch (in.byte() % 10) {
        case 5:  // a byte flipped on the wire
          d.pump();
          if (!d.wire.empty()) d.wire[in.byte() % d.wire.size()] ^= static_cast<char>(1 + in.byte() % 255);
          break;
        case 6:  // bytes lost on the wire
          d.pump();
          d.wire.erase(0, std::min<std::size_t>(d.wire.size(), 1 + in.byte() * 16u));
          break;
        case 7: {  // noise
          const std::string noise = in.text(64);
          const std::size_t n = std::min(noise.size(), buffer.size());
          std::copy_n(noise.begin(), n, buffer.begin());
          if (n > 0) return {StreamStatus::ok, n, {}};
          break;
        }
        case 8:  // nothing arrives in time
          d.now_ms += timeout.count();
          return {StreamStatus::timeout, 0, {}};
        case 9:
          switch (in.byte() % 4) {
            case 0: return unplug(0);
            case 1: return unplug(10 * in.byte());
            case 2: d.emulator.power_cycle(d.now_ms); break;
            default: d.now_ms += std::min<std::int64_t>(timeout.count(), in.byte()); break;
          }
          break;
        default: limit = std::min<std::size_t>(limit, 1 + in.byte() * 8u); break;
      }
    }
    d.pump();
    if (d.wire.empty()) {
      // Wait for the sensor's next scan, or the whole timeout.
      d.now_ms = std::max(d.now_ms, std::min(d.now_ms + timeout.count(), d.emulator.next_due_ms()));
      d.pump();
    }
    if (d.wire.empty()) return {StreamStatus::timeout, 0, {}};
    const std::size_t n = std::min(limit, d.wire.size());
    std::copy_n(d.wire.begin(), n, buffer.begin());
    d.wire.erase(0, n);
    return {StreamStatus::ok, n, {}};
  }

  StreamResult write(std::string_view bytes, std::chrono::milliseconds timeout) override {
    if (generation_ != device_.generation) return closed();
    Device& d = device_;
    if (!d.perfect()) {
      const std::uint8_t op = d.script.byte() % 8;
      if (op == 6) {  // the port takes only part of it in time
        const std::size_t n = d.script.byte() % (bytes.size() + 1);
        d.pump();
        d.emulator.receive(bytes.substr(0, n), d.now_ms);
        d.now_ms += timeout.count();
        return {StreamStatus::timeout, n, {}};
      }
      if (op == 7) return unplug(10 * d.script.byte());
    }
    d.pump();
    d.emulator.receive(bytes, d.now_ms);
    d.pump();
    return {StreamStatus::ok, bytes.size(), {}};
  }

  void discard_input() override { device_.wire.clear(); }
  const std::string& name() const override { return name_; }

 private:
  StreamResult closed() const { return {StreamStatus::closed, 0, name_ + ": read failed: Input/output error"}; }
  StreamResult unplug(std::int64_t absent_ms) {
    ++device_.generation;
    device_.absent_until_ms = device_.now_ms + absent_ms;
    device_.wire.clear();
    return {StreamStatus::closed, 0, name_ + ": the device vanished (No such device)"};
  }
  Device& device_;
  std::uint64_t generation_;
  std::string name_ = "/dev/fuzz-urg";
};

}  // namespace

STRIDEMAP_FUZZ_TARGET(scip_driver) {
  fuzz::ByteReader script(data);
  UrgEmulatorOptions emulator_options;
  emulator_options.variant = script.byte() % 2 ? UrgVariant::ug01 : UrgVariant::classic;
  emulator_options.timestamp_start_ms = (1u << 24) - 1 - script.integer<std::uint16_t>();
  UrgDriverOptions options;
  const std::uint8_t shape = script.byte();
  options.cluster = shape % 3;
  options.scan_interval = (shape >> 2) % 3;
  options.two_char_values = (shape >> 4) & 1;
  if ((shape >> 5) & 1) {
    options.start_step = 100;
    options.end_step = 600;
  }
  options.probe_attempts = 1 + (shape >> 6) % 3;

  Device device(script, emulator_options);
  options.monotonic_clock = [&device] { return static_cast<double>(device.now_ms) / 1000.0; };
  options.host_clock = [&device] { return 1.7e9 + static_cast<double>(device.now_ms) / 1000.0; };
  options.sleep = [&device](double s) { device.now_ms += static_cast<std::int64_t>(std::ceil(s * 1000.0)); };
  const ByteStreamOpener opener = [&device](std::string& error) -> std::unique_ptr<ByteStream> {
    if (device.now_ms < device.absent_until_ms) {
      error = "cannot open /dev/fuzz-urg: No such file or directory";
      return nullptr;
    }
    ++device.generation;
    device.wire.clear();  // a new session starts with an empty port (stale bytes were the script's to invent)
    return std::make_unique<FakeStream>(device);
  };

  const std::size_t heap_before = heap_in_use();
  std::uint64_t scans = 0, scans_when_perfect = 0;
  double previous_host_time = -1.0;
  std::int64_t perfect_since_ms = -1;
  {
    UrgDriver driver(opener, options);
    UrgDriverEvent event;
    while (true) {
      if (device.perfect() && perfect_since_ms < 0) perfect_since_ms = device.now_ms;
      if (perfect_since_ms >= 0 && device.now_ms - perfect_since_ms > 20000) break;
      if (device.now_ms > 3'600'000) break;  // an hour of script is plenty
      const std::int64_t before = device.now_ms;
      const bool got = driver.next(event, 0.2);
      check(device.now_ms - before <= 200 + 1000 + 2, "next(0.2 s) took " + std::to_string(device.now_ms - before) +
                                                          " ms of virtual time");
      check(heap_in_use() <= heap_before + (8u << 20), "the driver holds more than 8 MB");
      if (!got || event.kind != UrgDriverEvent::Kind::scan) continue;
      const UrgScan& s = event.scan;
      check(s.sequence == scans, "scan " + std::to_string(s.sequence) + " delivered as number " + std::to_string(scans));
      ++scans;
      if (perfect_since_ms >= 0) ++scans_when_perfect;
      check(std::isfinite(s.host_time_s) && std::isfinite(s.host_receive_time_s), "a scan time that is not finite");
      const int first_step = options.start_step >= 0 ? options.start_step : driver.parameters().first_step;
      check(s.raw.first_step == first_step, "a scan of other steps than requested");
      check(!s.raw.values_mm.empty(), "an empty scan");
      if (!s.first_after_start && previous_host_time >= 0.0) {
        check(s.host_time_s > previous_host_time, "host time of a scan not after the previous one's");
      }
      previous_host_time = s.host_time_s;
    }
    check(scans_when_perfect > 0, "the link was perfect for 20 s and no scan came");
    check(driver.state() == UrgDriverState::streaming, "not streaming after 20 s of a perfect link");
  }
}
