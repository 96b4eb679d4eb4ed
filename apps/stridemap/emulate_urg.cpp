// `stridemap emulate-urg`: a URG-04LX on a pseudo-terminal, measuring a
// simulated scene (or replaying recorded scans), with faults on request
// (docs/emulator.md).
#include <cmath>
#include <cstdio>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

#include "cli_parsing.hpp"
#include "commands.hpp"
#include "output_guard.hpp"
#include "stridemap/config/mapper_config.hpp"
#include "stridemap/config/scene_yaml.hpp"
#include "stridemap/core/error.hpp"
#include "stridemap/experiments/cart_rail.hpp"
#include "stridemap/live/emulator_server.hpp"
#include "stridemap/recordings/recorded_scans.hpp"
#include "stridemap/sim/footprint_beam_model.hpp"
#include "stridemap/sim/walk_motion.hpp"
#include "urg_device.hpp"

namespace stridemap::cli {
namespace {

struct EmulateArgs {
  std::string scene_path;
  std::string replay_path;
  bool overwrite = false;
  std::string motion = "static";
  double x_m = 0.0, y_m = 0.0, yaw_deg = 0.0, pitch_deg = 0.0, roll_deg = 0.0;
  std::string config_path;
  std::string variant = "classic";
  int rate_hz = 10;
  std::uint64_t seed = 1;
  std::string mixed_pixels = "off";
  std::uint32_t timestamp_start_ms = 0;
  std::vector<std::string> faults;
  std::string poses_clock = "host";
  EmulatorServerOptions server;
};

constexpr double kDegree = std::numbers::pi / 180.0;

std::unique_ptr<MotionSource> make_motion(const EmulateArgs& args, const Scene* scene, double period_s) {
  if (args.motion == "static") {
    TrunkPose pose;
    pose.x_m = args.x_m;
    pose.y_m = args.y_m;
    pose.yaw_rad = args.yaw_deg * kDegree;
    pose.pitch_rad = args.pitch_deg * kDegree;
    pose.roll_rad = args.roll_deg * kDegree;
    return std::make_unique<StaticMotion>(pose);
  }
  if (args.motion == "cart-rail") {
    const CartRailPath rail = scene && scene->cart_rail ? *scene->cart_rail : CartRailOptions{}.default_rail;
    return std::make_unique<CartRailMotion>(rail, period_s);
  }
  if (args.motion == "walk") {
    if (!scene) throw InputError("--motion walk: needs --scene with a walk_path section");
    return std::make_unique<WalkMotion>(*scene);
  }
  throw InputError("--motion: '" + args.motion + "' is not available; use static, cart-rail or walk");
}

void run_emulate(EmulateArgs& args) {
  install_stop_signals();
  if ((args.scene_path.empty()) == (args.replay_path.empty())) {
    throw InputError("emulate-urg: give either --scene (simulate) or --replay (recorded scans), not both");
  }
  if (args.rate_hz <= 0 || 60000 % (args.rate_hz * 60) != 0) {
    throw InputError("--rate-hz " + std::to_string(args.rate_hz) +
                     " does not give a whole number of milliseconds per scan (use 10, 20, 25, 40, 50, 100...)");
  }
  if (args.poses_clock != "host" && args.poses_clock != "sensor") {
    throw InputError("--poses-clock: '" + args.poses_clock + "' is not a clock; use host or sensor");
  }
  if (args.variant != "classic" && args.variant != "ug01") {
    throw InputError("--variant: '" + args.variant + "' is not a URG-04LX variant; use classic or ug01");
  }
  UrgEmulatorOptions options;
  options.variant = args.variant == "ug01" ? UrgVariant::ug01 : UrgVariant::classic;
  options.parameters.motor_speed_rpm = args.rate_hz * 60;
  options.timestamp_start_ms = args.timestamp_start_ms;
  options.validate();
  const UrgParameters urg = scip::to_urg_parameters(options.parameters);

  for (const std::string& f : args.faults) args.server.faults.push_back(parse_emulator_fault(f));
  {
    const ExistingLog choice = existing_log_choice(args.overwrite, false);
    const std::vector<NamedPath> inputs{
        {"--scene", args.scene_path}, {"--replay", args.replay_path}, {"--config", args.config_path}};
    for (const auto& [option, path] : {std::pair<std::string, std::string>{"--trace", args.server.trace_path},
                                       {"--poses-out", args.server.poses_path}}) {
      if (path.empty()) continue;
      refuse_output_that_is_an_input(option, path, inputs);
      check_log_output(option, path, choice, "");
    }
    if (!args.server.trace_path.empty() && args.server.trace_path == args.server.poses_path) {
      throw InputError("--trace and --poses-out name the same file");
    }
  }
  args.server.pose_clock = args.poses_clock == "sensor" ? PoseClock::sensor : PoseClock::host;

  std::unique_ptr<Scene> scene;
  std::unique_ptr<MotionSource> motion;
  std::unique_ptr<UrgScanSource> source;
  std::string what;
  if (!args.scene_path.empty()) {
    scene = std::make_unique<Scene>(load_scene_yaml(args.scene_path));
    const SensorMount mount = args.config_path.empty() ? SensorMount{} : load_mapper_config(args.config_path).mount;
    motion = make_motion(args, scene.get(), urg.scan_period_s);
    const bool footprint = args.mixed_pixels == "on";
    if (!footprint && args.mixed_pixels != "off") {
      throw InputError("--mixed-pixels: expected on or off, got '" + args.mixed_pixels + "'");
    }
    std::unique_ptr<BeamModel> beam;
    if (footprint) {
      beam = std::make_unique<FootprintBeamModel>();
    } else {
      beam = std::make_unique<SingleRayBeamModel>();
    }
    auto simulator = std::make_unique<UrgSimulator>(*scene, urg, UrgSimOptions{}, args.seed, std::move(beam));
    source = std::make_unique<SimulatedScanSource>(std::move(simulator), *motion, mount, args.seed);
    what = "simulating " + args.scene_path + ", " + motion->describe() + (footprint ? ", footprint beam model" : "");
  } else {
    io::RecordedScans recorded = io::read_recorded_scans(args.replay_path);
    what = "replaying " + std::to_string(recorded.scans.size()) + " " + recorded.format + " scans from " +
           args.replay_path;
    source = std::make_unique<RecordedScanSource>(std::move(recorded.scans), recorded.first_step, recorded.cluster, urg);
    if (!args.server.poses_path.empty()) {
      throw InputError("--poses-out needs a simulated motion (--scene); a replay has no poses");
    }
  }
  UrgEmulator emulator(options, *source);
  std::fprintf(stderr, "emulate-urg: %s (%s, %d Hz); Ctrl-C stops\n", what.c_str(), args.variant.c_str(),
               args.rate_hz);
  const EmulatorServerStats stats = run_emulator_server(
      emulator, motion.get(), args.server, stop_flag(),
      [](const std::string& line) { std::fprintf(stderr, "emulate-urg: %s\n", line.c_str()); });
  std::printf("emulate-urg: %llu frames: %llu sent, %llu corrupted, %llu dropped, %llu lost (stall, disconnect, "
              "reset, unread)\n",
              static_cast<unsigned long long>(stats.frames), static_cast<unsigned long long>(stats.sent),
              static_cast<unsigned long long>(stats.corrupted), static_cast<unsigned long long>(stats.dropped),
              static_cast<unsigned long long>(stats.lost));
}

}  // namespace

void register_emulate_urg(CLI::App& app) {
  auto args = std::make_shared<EmulateArgs>();
  CLI::App* cmd = app.add_subcommand("emulate-urg", "A URG-04LX on a pseudo-terminal: simulated or replayed scans, "
                                                    "faults on request (docs/emulator.md)");
  cmd->add_option("--scene", args->scene_path, "Scene to measure (YAML, docs/scenes.md)");
  cmd->add_option("--replay", args->replay_path, "Replay recorded scans instead: a scan log or a BreezySLAM log");
  cmd->add_option("--motion", args->motion,
                  "static, cart-rail (the scene's rail, as experiment cart-rail) or walk (the scene's walk_path, "
                  "as experiment rocky-walk)")
      ->capture_default_str();
  cmd->add_option("--x-m", args->x_m, "static: trunk position x [m]")->capture_default_str()
      ->check(number_from_to(-1e6, 1e6, "m"));
  cmd->add_option("--y-m", args->y_m, "static: trunk position y [m]")->capture_default_str()
      ->check(number_from_to(-1e6, 1e6, "m"));
  cmd->add_option("--yaw-deg", args->yaw_deg, "static: heading [deg]")->capture_default_str()
      ->check(number_from_to(-360.0, 360.0, "deg"));
  cmd->add_option("--pitch-deg", args->pitch_deg, "static: trunk pitch, nose down positive [deg]")->capture_default_str()
      ->check(number_from_to(-90.0, 90.0, "deg"));
  cmd->add_option("--roll-deg", args->roll_deg, "static: trunk roll [deg]")->capture_default_str()
      ->check(number_from_to(-90.0, 90.0, "deg"));
  cmd->add_option("--config", args->config_path, "Mapper configuration whose sensor mount the simulation uses");
  cmd->add_option("--link", args->server.link_path, "Symlink to create for the emulated serial port")->required();
  cmd->add_option("--variant", args->variant, "classic (boots in SCIP 1.1) or ug01 (SCIP 2.0 native)")
      ->capture_default_str();
  cmd->add_option("--rate-hz", args->rate_hz, "Scans per second (a real URG-04LX: 10; faster for tests)")
      ->capture_default_str()
      ->check(whole_from_to(1, 1000));
  cmd->add_option("--seed", args->seed, "Seed of the simulated noise")->capture_default_str()
      ->check(seed_value());
  cmd->add_option("--mixed-pixels", args->mixed_pixels, "on: the footprint beam model (mixed pixels at edges)")
      ->capture_default_str();
  cmd->add_option("--timestamp-start-ms", args->timestamp_start_ms,
                  "Sensor clock at power-up (e.g. 16776000 to see the 24-bit wrap within a second)")
      ->capture_default_str()
      ->check(whole_from_to(0, 4294967295u));
  cmd->add_option("--fault", args->faults,
                  "KIND@FRAME[:SECONDS]: corrupt@20, drop@30, stall@40:1.5, disconnect@60:1, reset@80 (repeatable)");
  cmd->add_option("--corrupt-probability", args->server.corrupt_probability, "Chance per frame of a corrupted byte")
      ->capture_default_str()
      ->check(number_from_to(0.0, 1.0));
  cmd->add_option("--drop-probability", args->server.drop_probability, "Chance per frame of a dropped frame")
      ->capture_default_str()
      ->check(number_from_to(0.0, 1.0));
  cmd->add_option("--fault-seed", args->server.fault_seed, "Seed of the random faults")->capture_default_str()
      ->check(seed_value());
  cmd->add_option("--trace", args->server.trace_path, "Write what happened to every frame to this file");
  cmd->add_flag("--overwrite", args->overwrite, "Replace an existing --trace or --poses-out file (refused by default)");
  cmd->add_option("--poses-out", args->server.poses_path, "Write the true pose of every scan (pose format)");
  cmd->add_option("--poses-clock", args->poses_clock, "Clock of --poses-out: host or sensor")->capture_default_str();
  cmd->add_option("--poses-rate-hz", args->server.poses_rate_hz,
                  "Poses per second in --poses-out, each written when its time comes (0: one per scan, at its "
                  "step 0)")
      ->capture_default_str()
      ->check(number_from_to(0.0, 10000.0, "Hz"));
  cmd->add_option("--max-frames", args->server.max_frames, "Stop after this many scan frames (0: no limit)")
      ->capture_default_str()
      ->check(whole_from_to(0, std::numeric_limits<std::uint64_t>::max()));
  cmd->add_option("--duration-s", args->server.max_duration_s, "Stop after this many seconds (0: no limit)")
      ->capture_default_str()
      ->check(number_from_to(0.0, 31536000.0, "s"));
  cmd->callback([args] { run_emulate(*args); });
}

}  // namespace stridemap::cli
