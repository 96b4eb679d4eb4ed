#pragma once
// The URG emulator serving a simulated cart-rail run on a pseudo-terminal,
// on its own thread, for the tests that drive a real UrgDriver through it
// (emulator_link_test.cpp, live_mapping_test.cpp).
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <future>
#include <memory>
#include <string>
#include <thread>

#include "stridemap/config/scene_yaml.hpp"
#include "stridemap/live/emulator_server.hpp"
#include "stridemap/sensors/urg_driver.hpp"
#include "stridemap/sim/urg_scan_source.hpp"
#include "test_paths.hpp"

namespace stridemap::test_emulator {

inline constexpr int kRateHz = 100;  // ten times a real unit, so the tests are quick
inline constexpr std::int64_t kPeriodMs = 1000 / kRateHz;
inline constexpr std::uint64_t kSeed = 5;

// Everything the emulator needs to simulate the cart on the rail.
struct Simulation {
  Simulation() : scene(load_scene_yaml(std::string(STRIDEMAP_SOURCE_DIR) + "/scenes/cart_rail_boxes.yaml")) {
    options.parameters.motor_speed_rpm = kRateHz * 60;
    urg = scip::to_urg_parameters(options.parameters);
    motion = std::make_unique<CartRailMotion>(*scene.cart_rail, urg.scan_period_s);
  }
  std::unique_ptr<SimulatedScanSource> make_source() const {
    auto simulator = std::make_unique<UrgSimulator>(scene, urg, UrgSimOptions{}, kSeed);
    return std::make_unique<SimulatedScanSource>(std::move(simulator), *motion, SensorMount{}, kSeed);
  }
  Scene scene;
  UrgEmulatorOptions options;
  UrgParameters urg;
  std::unique_ptr<CartRailMotion> motion;
};

// The emulator server on its own thread, stopped and joined on destruction.
class RunningEmulator {
 public:
  RunningEmulator(const Simulation& sim, EmulatorServerOptions options)
      : source_(sim.make_source()), emulator_(sim.options, *source_) {
    std::promise<void> ready;
    std::future<void> started = ready.get_future();
    thread_ = std::thread([this, options, &sim, ready = std::move(ready)]() mutable {
      bool told = false;
      try {
        stats_ = run_emulator_server(emulator_, sim.motion.get(), options, stop_, [&](const std::string&) {
          if (!told) ready.set_value();
          told = true;
        });
      } catch (...) {
        if (!told) ready.set_exception(std::current_exception());
        told = true;
      }
      if (!told) ready.set_value();
    });
    if (started.wait_for(std::chrono::seconds(10)) != std::future_status::ready) {
      ADD_FAILURE() << "the emulator did not start";
      return;
    }
    started.get();
  }
  ~RunningEmulator() {
    stop_.store(true);
    thread_.join();
  }
  const EmulatorServerStats& stats() const { return stats_; }

 private:
  std::unique_ptr<SimulatedScanSource> source_;
  UrgEmulator emulator_;
  std::atomic<bool> stop_{false};
  EmulatorServerStats stats_;
  std::thread thread_;
};


// Reads the driver's events until it reports the sensor connected, for at
// most 10 s; returns the last event for the test to check.
inline UrgDriverEvent wait_until_connected(UrgDriver& driver) {
  UrgDriverEvent event;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (std::chrono::steady_clock::now() < deadline) {
    if (driver.next(event, 0.1) && event.kind == UrgDriverEvent::Kind::connected) break;
  }
  return event;
}

}  // namespace stridemap::test_emulator
