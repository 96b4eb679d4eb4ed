// `stridemap import FORMAT FILE`: BreezySLAM, CARMEN, CSV-range, point-pair
// and TUM files into a stridemap scan log and pose file, which `stridemap map`
// then maps like any recording (docs/import.md).

#include <cstdio>
#include <functional>
#include <memory>
#include <cmath>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include "cli_parsing.hpp"
#include "commands.hpp"
#include "output_guard.hpp"
#include "terminal_output.hpp"
#include "stridemap/core/printable_text.hpp"
#include "stridemap/core/error.hpp"
#include "stridemap/recordings/log_import.hpp"

namespace stridemap::cli {
namespace {

constexpr double kRadPerDeg = std::numbers::pi / 180.0;
constexpr std::size_t kProblemsShown = 20;

struct ImportArgs {
  std::string input;
  std::string log_path;
  std::string poses_path;
  bool overwrite = false;
  io::BreezySlamImportOptions breezyslam;
  io::CarmenImportOptions carmen;
  double flaser_fov_deg = 180.0;
  io::CsvRangesImportOptions csv;
  double angle_min_deg = -119.53125;  // step 44 of the URG-04LX
  double angle_step_deg = 0.3515625;  // 360 / 1024
  std::string tum_height = "reference";
  io::XyImportOptions xy;
  std::string xy_encoding = "int32";
  std::vector<double> invalid_pair{0.0, 0.0};
  std::vector<double> static_pose;
  double scan_rate_hz = 0.0;  // 0: not given
  std::optional<double> xy_angle_min_deg;
  std::optional<double> xy_angle_step_deg;
};

// X,Y,YAW or X,Y,Z,ROLL,PITCH,YAW: metres and degrees, as the tool's other pose options.
TrunkPose static_pose_of(const std::vector<double>& v) {
  if (v.size() != 3 && v.size() != 6) {
    throw InputError("--static-pose: expected X,Y,YAW or X,Y,Z,ROLL,PITCH,YAW, got " + std::to_string(v.size()) +
                     " numbers");
  }
  for (const double value : v) {
    if (!std::isfinite(value)) throw InputError("--static-pose: expected finite numbers");
  }
  TrunkPose pose;
  pose.x_m = v[0];
  pose.y_m = v[1];
  pose.yaw_rad = v.back() * kRadPerDeg;
  if (v.size() == 6) {
    pose.z_m = v[2];
    pose.roll_rad = v[3] * kRadPerDeg;
    pose.pitch_rad = v[4] * kRadPerDeg;
    if (std::abs(v[3]) > 90.0 || std::abs(v[4]) > 90.0) {
      throw InputError("--static-pose: roll and pitch are degrees from -90 to 90, got " + std::to_string(v[3]) + " and " +
                       std::to_string(v[4]));
    }
  }
  return pose;
}

// The importer of one format, told where to report its progress.
using Importer = std::function<io::ImportedData(std::string_view text, const ProgressCallback& progress)>;

void run_import(const ImportArgs& args, const Importer& import, bool binary = false) {
  refuse_existing_files({{"--log", args.log_path}, {"--poses", args.poses_path}}, args.overwrite);
  const std::string text = io::read_import_file(args.input, !binary);
  note("read " + std::to_string(text.size()) + " bytes from " + args.input);
  io::ImportedData data;
  {
    io::ProgressBar bar = progress_bar("import", "kB");
    data = import(text, bar.callback());
  }
  const io::ImportReport& r = data.report;
  for (std::size_t k = 0; k < r.problems.size() && k < kProblemsShown; ++k) {
    std::fprintf(stderr, "stridemap: warning: %s (line skipped)\n", r.problems[k].c_str());
  }
  if (r.skipped > kProblemsShown) {
    std::fprintf(stderr, "stridemap: warning: %zu more lines skipped\n", r.skipped - kProblemsShown);
  }
  const std::size_t malformed = r.skipped - r.out_of_order;
  if (data.scans.empty() && data.poses.empty()) {
    throw InputError(args.input + ": nothing to import (" + std::to_string(r.lines) + " lines, " +
                     std::to_string(malformed) + " malformed, " + std::to_string(r.ignored) + " of other kinds)");
  }
  io::write_imported(data, data.scans.empty() ? "" : args.log_path, data.poses.empty() ? "" : args.poses_path,
                     args.input);
  std::printf("import %s: %zu scans, %zu poses from %zu lines of %s (%zu malformed lines skipped, %zu out of time "
              "order skipped, %zu of other kinds ignored)",
              data.format.c_str(), r.scans, r.poses, r.lines, args.input.c_str(), malformed, r.out_of_order,
              r.ignored);
  if (!data.scans.empty()) std::printf("; scan log: %s", printable_text(args.log_path).c_str());
  if (!data.poses.empty()) std::printf("; poses: %s", printable_text(args.poses_path).c_str());
  std::printf("\n");
}

CLI::App* add_format(CLI::App& parent, const char* name, const char* help, ImportArgs& args, bool scans, bool poses) {
  CLI::App* command = parent.add_subcommand(name, help);
  command->add_option("file", args.input, "The file to import")->required();
  if (scans) command->add_option("--log", args.log_path, "Scan log to write (docs/live.md)")->required();
  if (poses) {
    command->add_option("--poses", args.poses_path, "Pose file to write (docs/live.md)")->required();
  }
  command->add_flag("--overwrite", args.overwrite, "Replace existing output files");
  return command;
}

}  // namespace

void register_import(CLI::App& app) {
  auto args = std::make_shared<ImportArgs>();
  CLI::App* import = app.add_subcommand(
      "import", "Other formats into a scan log and a pose file for `stridemap map` (docs/import.md)");
  import->require_subcommand(1);

  CLI::App* breezyslam = add_format(*import, "breezyslam", "BreezySLAM log: URG-04LX scans and wheel odometry",
                                    *args, true, true);
  breezyslam->add_option("--wheel-radius-m", args->breezyslam.wheel_radius_m, "Wheel radius")->capture_default_str();
  breezyslam->add_option("--half-axle-m", args->breezyslam.half_axle_length_m, "Half the distance between the wheels")
      ->capture_default_str();
  breezyslam->add_option("--ticks-per-revolution", args->breezyslam.ticks_per_revolution,
                         "Encoder ticks per wheel revolution")
      ->capture_default_str();
  breezyslam->add_option("--values-per-scan", args->breezyslam.values_per_scan, "Ranges per line")
      ->capture_default_str();
  breezyslam->add_option("--first-step", args->breezyslam.first_step, "URG step of the first range")
      ->capture_default_str();
  breezyslam->callback([args] {
    run_import(*args, [&](std::string_view text, const ProgressCallback& progress) {
      auto options = args->breezyslam;
      options.progress = progress;
      return io::import_breezyslam(text, args->input, options);
    });
  });

  CLI::App* carmen = add_format(*import, "carmen", "CARMEN log: FLASER / ROBOTLASER1 lines with the robot's pose",
                                *args, true, true);
  carmen->add_option("--flaser-fov-deg", args->flaser_fov_deg, "Field of view of FLASER scans")->capture_default_str();
  carmen->add_option("--flaser-max-range-m", args->carmen.flaser_max_range_m, "Maximum range of FLASER scans")
      ->capture_default_str();
  carmen->add_option("--min-range-m", args->carmen.min_range_m, "Shorter ranges are no return")->capture_default_str();
  carmen->callback([args] {
    args->carmen.flaser_field_of_view_rad = args->flaser_fov_deg * kRadPerDeg;
    run_import(*args, [&](std::string_view text, const ProgressCallback& progress) {
      auto options = args->carmen;
      options.progress = progress;
      return io::import_carmen(text, args->input, options);
    });
  });

  CLI::App* csv = add_format(*import, "csv-ranges", "CSV ranges: time_s, r_0, r_1, ... per line", *args, true, false);
  csv->add_option("--angle-min-deg", args->angle_min_deg, "Angle of the first range (0 ahead, positive left)")
      ->capture_default_str();
  csv->add_option("--angle-step-deg", args->angle_step_deg, "Angle between ranges")->capture_default_str();
  csv->add_option("--range-scale-m", args->csv.range_scale_m, "Metres per unit of the ranges (0.001: millimetres)")
      ->capture_default_str();
  csv->add_option("--min-range-m", args->csv.min_range_m, "Shorter ranges are no return")->capture_default_str();
  csv->add_option("--max-range-m", args->csv.max_range_m, "Longer ranges are beyond the range")->capture_default_str();
  csv->callback([args] {
    args->csv.angle_min_rad = args->angle_min_deg * kRadPerDeg;
    args->csv.angle_step_rad = args->angle_step_deg * kRadPerDeg;
    run_import(*args, [&](std::string_view text, const ProgressCallback& progress) {
      auto options = args->csv;
      options.progress = progress;
      return io::import_csv_ranges(text, args->input, options);
    });
  });

  CLI::App* xy = add_format(*import, "xy", "Point pairs: each scan the (x, y) of every beam's return", *args, true,
                            false);
  xy->add_option("--encoding", args->xy_encoding, "int32 or float32 (binary, little-endian), or text (a scan a line)")
      ->capture_default_str();
  xy->add_option("--header-bytes", args->xy.header_bytes, "Binary: bytes before the first value")->capture_default_str();
  xy->add_option("--separator", args->xy.separator, "Binary: a pair with x and y both this ends a scan");
  xy->add_option("--pairs-per-scan", args->xy.pairs_per_scan, "Binary without a separator: pairs in every scan");
  xy->add_option("--unit-m", args->xy.unit_m, "Metres per unit of x and y (0.001: millimetres)")->capture_default_str();
  xy->add_option("--invalid", args->invalid_pair, "The pair X,Y meaning no return (default 0,0)")
      ->delimiter(',')
      ->expected(2);
  xy->add_flag("--time-first", args->xy.time_first, "Text: the first number of each line is the scan's time [s]");
  xy->add_option("--scan-rate-hz", args->scan_rate_hz, "Scans without times: the sensor's rate (scan k at k / rate s)")
      ->check(number_from_to(1e-6, 10000.0, "Hz"));
  xy->add_option("--angle-min-deg", args->xy_angle_min_deg, "Angle of the first beam (default: fitted to the points)");
  xy->add_option("--angle-step-deg", args->xy_angle_step_deg, "Angle between beams (default: fitted to the points)");
  xy->add_option("--min-range-m", args->xy.min_range_m, "Shorter ranges are no return")->capture_default_str();
  xy->add_option("--max-range-m", args->xy.max_range_m, "Longer ranges are beyond the range")->capture_default_str();
  xy->add_option("--static-pose", args->static_pose,
                 "The sensor stood still: also write --poses with X,Y,YAW or X,Y,Z,ROLL,PITCH,YAW (m, deg) at every "
                 "scan's time")
      ->delimiter(',')
      ->expected(3, 6);
  xy->add_option("--poses", args->poses_path, "Pose file to write with --static-pose");
  xy->callback([args] {
    io::XyImportOptions options = args->xy;
    if (args->xy_encoding == "int32") {
      options.encoding = io::XyEncoding::int32;
    } else if (args->xy_encoding == "float32") {
      options.encoding = io::XyEncoding::float32;
    } else if (args->xy_encoding == "text") {
      options.encoding = io::XyEncoding::text;
    } else {
      throw InputError("--encoding: '" + args->xy_encoding + "' is not one of int32, float32, text");
    }
    options.invalid_x = args->invalid_pair[0];
    options.invalid_y = args->invalid_pair[1];
    if (args->scan_rate_hz > 0.0) options.scan_rate_hz = args->scan_rate_hz;
    if (args->xy_angle_min_deg) options.angle_min_rad = *args->xy_angle_min_deg * kRadPerDeg;
    if (args->xy_angle_step_deg) options.angle_step_rad = *args->xy_angle_step_deg * kRadPerDeg;
    if (args->static_pose.empty() != args->poses_path.empty()) {
      throw InputError("--static-pose and --poses go together: the pose file is written from the pose");
    }
    if (!args->static_pose.empty()) options.static_pose = static_pose_of(args->static_pose);
    run_import(*args, [&](std::string_view bytes, const ProgressCallback& progress) {
      options.progress = progress;
      return io::import_xy(bytes, args->input, options);
    }, options.encoding != io::XyEncoding::text);
  });

  CLI::App* tum = add_format(*import, "tum", "TUM trajectory: timestamp tx ty tz qx qy qz qw", *args, false, true);
  tum->add_option("--z", args->tum_height,
                  "What tz (relative to the first pose) becomes: reference (h_ref), height-change, ignore")
      ->capture_default_str();
  tum->callback([args] {
    io::TumImportOptions options;
    if (args->tum_height == "reference") {
      options.height = io::TumHeight::reference_elevation;
    } else if (args->tum_height == "height-change") {
      options.height = io::TumHeight::height_change;
    } else if (args->tum_height == "ignore") {
      options.height = io::TumHeight::ignore;
    } else {
      throw InputError("--z: '" + args->tum_height + "' is not one of reference, height-change, ignore");
    }
    run_import(*args, [&](std::string_view text, const ProgressCallback& progress) {
      options.progress = progress;
      return io::import_tum(text, args->input, options);
    });
  });
}

}  // namespace stridemap::cli
