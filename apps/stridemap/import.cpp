// `stridemap import FORMAT FILE`: BreezySLAM, CARMEN, CSV-range and TUM
// files into a stridemap scan log and pose file, which `stridemap map`
// then maps like any recording (docs/import.md).
#include <sys/stat.h>

#include <cstdio>
#include <functional>
#include <memory>
#include <numbers>
#include <string>

#include "commands.hpp"
#include "terminal_output.hpp"
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
};

void refuse_existing(const std::string& path, bool overwrite) {
  struct stat info {};
  if (!path.empty() && !overwrite && ::stat(path.c_str(), &info) == 0 && S_ISREG(info.st_mode)) {
    throw InputError(path + ": already exists; choose another name or pass --overwrite");
  }
}

// The importer of one format, told where to report its progress.
using Importer = std::function<io::ImportedData(std::string_view text, const ProgressCallback& progress)>;

void run_import(const ImportArgs& args, const Importer& import) {
  refuse_existing(args.log_path, args.overwrite);
  refuse_existing(args.poses_path, args.overwrite);
  const std::string text = io::read_import_text(args.input);
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
  if (!data.scans.empty()) std::printf("; scan log: %s", args.log_path.c_str());
  if (!data.poses.empty()) std::printf("; poses: %s", args.poses_path.c_str());
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
