// `stridemap calibrate-range`: the procedure of Fig. 6. Fits the cubic range
// correction to (measured, true) pairs and shows how well it fits, so that a
// user can judge the result before pasting it into a config.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "commands.hpp"
#include "output_guard.hpp"
#include "stridemap/core/printable_text.hpp"
#include "stridemap/config/calibration_csv.hpp"
#include "stridemap/core/error.hpp"
#include "stridemap/io/text_file.hpp"
#include "stridemap/sensors/range_calibration.hpp"

namespace stridemap::cli {
namespace {

struct CalibrateRangeOptions {
  std::string csv_path;
  std::string json_path;  ///< empty: no JSON output
  bool overwrite = false;
};

constexpr const char* coefficient_units[4] = {"m", "-", "1/m", "1/m^2"};

void print_report(const std::string& source, const RangePairs& pairs,
                  const RangeCalibrationFit& fit, double min_measured_m, double max_measured_m) {
  const auto& c = fit.calibration.coefficients;
  std::printf("Range calibration from %s: %zu pairs, measured ranges %.4f to %.4f m\n",
              source.c_str(), pairs.measured_m.size(), min_measured_m, max_measured_m);
  std::printf("corrected = r + c0 + c1 r + c2 r^2 + c3 r^3   (r = measured range [m])\n");
  for (std::size_t k = 0; k < c.size(); ++k) {
    std::printf("  c%zu = %+.9e  [%s]\n", k, c[k], coefficient_units[k]);
  }
  std::printf("The cubic is only trustworthy between the smallest and largest measured range.\n\n");
  std::printf("%6s %14s %14s %15s %15s\n", "line", "measured [m]", "true [m]", "corrected [m]",
              "residual [mm]");
  for (std::size_t i = 0; i < pairs.measured_m.size(); ++i) {
    std::printf("%6d %14.6f %14.6f %15.6f %15.3f\n", pairs.line[i], pairs.measured_m[i],
                pairs.true_m[i], fit.calibration.corrected_m(pairs.measured_m[i]),
                fit.residuals_m[i] * 1000.0);
  }
  std::printf("\nrms residual: %.3f mm, max |residual|: %.3f mm\n\n", fit.rms_residual_m * 1000.0,
              fit.max_abs_residual_m * 1000.0);
  std::printf("For a YAML config:\nrange_calibration: {coefficients: [%.9g, %.9g, %.9g, %.9g]}\n",
              c[0], c[1], c[2], c[3]);
}

void write_json(const std::string& path, const std::string& source, const RangePairs& pairs,
                const RangeCalibrationFit& fit, double min_measured_m, double max_measured_m) {
  nlohmann::json rows = nlohmann::json::array();
  for (std::size_t i = 0; i < pairs.measured_m.size(); ++i) {
    rows.push_back({{"line", pairs.line[i]},
                    {"measured_m", pairs.measured_m[i]},
                    {"true_m", pairs.true_m[i]},
                    {"corrected_m", fit.calibration.corrected_m(pairs.measured_m[i])},
                    {"residual_m", fit.residuals_m[i]}});
  }
  const auto& c = fit.calibration.coefficients;
  const nlohmann::json document = {
      {"source_csv", source},
      {"model", "corrected = r + c0 + c1 r + c2 r^2 + c3 r^3, r in metres"},
      {"coefficients", {c[0], c[1], c[2], c[3]}},
      {"coefficient_units", {"m", "-", "1/m", "1/m^2"}},
      {"valid_measured_range_m", {min_measured_m, max_measured_m}},
      {"rms_residual_m", fit.rms_residual_m},
      {"max_abs_residual_m", fit.max_abs_residual_m},
      {"pairs", rows}};
  io::write_text_file(path, document.dump(2) + "\n", "calibration JSON");
}

void run(const CalibrateRangeOptions& options) {
  refuse_output_that_is_an_input("--json", options.json_path, {{"--csv", options.csv_path}});
  refuse_existing_files({{"--json", options.json_path}}, options.overwrite);
  const RangePairs pairs = read_range_pairs_csv(options.csv_path);
  const RangeCalibrationFit fit = fit_range_calibration(pairs.measured_m, pairs.true_m);
  const auto [min_it, max_it] = std::minmax_element(pairs.measured_m.begin(), pairs.measured_m.end());
  print_report(options.csv_path, pairs, fit, *min_it, *max_it);
  if (!options.json_path.empty()) {
    write_json(options.json_path, options.csv_path, pairs, fit, *min_it, *max_it);
    std::printf("\nwrote %s\n", printable_text(options.json_path).c_str());
  }
}

}  // namespace

void register_calibrate_range(CLI::App& app) {
  auto options = std::make_shared<CalibrateRangeOptions>();
  CLI::App* command = app.add_subcommand(
      "calibrate-range",
      "Fit the cubic range correction (paper eq. 4, Fig. 6) to (measured, true) range pairs");
  command
      ->add_option("--csv", options->csv_path,
                   "CSV with a header 'measured_m,true_m' or 'measured_mm,true_mm', one pair per line")
      ->required();
  command->add_option("--json", options->json_path,
                      "Also write coefficients, residuals and statistics to this JSON file");
  add_file_overwrite_flag(*command, options->overwrite, "--json");
  command->callback([options] { run(*options); });
}

}  // namespace stridemap::cli
