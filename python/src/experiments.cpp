// The paper's experiments (experiments/), run as the CLI's `experiment`
// commands run them, returning summary.json's content as a dict and writing
// the command's output folder when asked.
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <pybind11/stl.h>

#include "bindings.hpp"
#include "stridemap/config/scene_yaml.hpp"
#include "stridemap/experiments/cart_rail.hpp"
#include "stridemap/experiments/cart_rail_report.hpp"
#include "stridemap/experiments/rocky_walk.hpp"
#include "stridemap/experiments/rocky_walk_report.hpp"
#include "stridemap/experiments/urg_walk_sensor.hpp"
#include "stridemap/experiments/wall_range_calibration.hpp"
#include "stridemap/io/output_folder.hpp"

namespace stridemap::python {
namespace {

py::object json_to_dict(const std::string& text) { return py::module_::import("json").attr("loads")(text); }

// The set appears whole or not at all, and a folder holding anything but an
// earlier run's outputs is refused (io/output_folder.hpp).
template <class Write>
void write_outputs(const std::optional<std::string>& out_dir, Write&& write) {
  if (!out_dir) return;
  io::OutputFolder staged(*out_dir, "out_dir");
  write(staged.path());
  staged.commit();
}

py::object run_rocky_walk_py(const FilePath& scene_path, std::uint64_t seed, const std::vector<double>& sweep,
                             const std::string& reference, bool calibrate_attitude, bool calibrate_range,
                             bool mixed_pixels, bool coupling, const std::string& filters,
                             const std::string& map_filter, double pose_error_scale,
                             const std::optional<std::string>& out_dir) {
  RockyWalkOptions options;
  options.walk.seed = seed;
  options.pose_error_scales = sweep;
  // The CLI's URG defaults (apps/stridemap/walk_experiments.cpp), so that the
  // same call gives the same summary from Python and from the shell.
  options.walk.pose_errors.reference = parse_enum_name<ReferenceElevationSource>(reference);
  options.calibrate_attitude = calibrate_attitude;
  options.sweep_references.push_back(ReferenceElevationSource::map_fused);
  options.walk.pose_errors = options.walk.pose_errors.scaled(finite_number(pose_error_scale, "pose_error_scale"));
  options.walk.map_filter = parse_map_filter(map_filter);
  options.validate();
  UrgWalkSensorOptions sensor;
  sensor.mixed_pixels = mixed_pixels;
  sensor.sim.receiver.enabled = coupling;
  sensor.filters = parse_scan_filter_list(filters.empty() ? (mixed_pixels ? "paper" : "none") : filters);
  std::optional<RangeCalibrationFit> range_calibration;
  // Before the flat-floor attitude calibration, as the CLI does.
  if (calibrate_range) {
    range_calibration = calibrate_range_on_wall(sensor.urg, sensor.sim, wall_calibration_seed(seed));
    sensor.calibration = range_calibration->calibration;
  }
  if (out_dir) io::check_output_folder(*out_dir, "out_dir");
  const Scene scene = load_scene_yaml(scene_path);
  if (!scene.walk_path) raise_input_error(scene_path.value + ": the scene has no walk_path section");
  const WalkSensorFactory factory = [sensor, seed](const Scene& s, const UpdateOptions& update) -> std::unique_ptr<WalkSensor> {
    return std::make_unique<UrgWalkSensor>(s, sensor, update, seed);
  };
  RockyWalkResult result;
  {
    py::gil_scoped_release release;
    result = run_rocky_walk(scene, *scene.walk_path, factory, options);
  }
  result.range_calibration = range_calibration;
  result.receiver_coupling = mixed_pixels && coupling;
  const RockyWalkRunInfo info{scene_path.value, scene_path.value + ":walk_path"};
  write_outputs(out_dir, [&](const std::string& folder) { write_rocky_walk_outputs(result, options, info, folder); });
  return json_to_dict(rocky_walk_summary_json(result, options, info));
}

py::object run_cart_rail_py(const FilePath& scene_path, const std::string& sensor, std::uint64_t seed,
                            std::optional<double> cell_size_m, int cells_per_side, bool mixed_pixels,
                            bool coupling, const std::string& filters, const std::optional<std::string>& map_filter,
                            const std::string& elevation_rule, const std::string& pipeline,
                            const std::optional<std::string>& out_dir) {
  CartRailOptions options;
  options.seed = seed;
  options.sensor = parse_enum_name<SimulatedSensor>(sensor);
  const bool urg = options.sensor == SimulatedSensor::urg;
  options.cell_size_m = cell_size_m.value_or(urg ? 0.01 : 0.005);
  options.cells_per_side = cells_per_side;
  options.update.elevation_rule = parse_enum_name<ElevationRule>(elevation_rule);
  options.mixed_pixels = mixed_pixels;
  options.sim.receiver.enabled = coupling;
  options.map_filter = parse_map_filter(map_filter.value_or(urg ? "fill" : "cas"));
  options.filters = parse_scan_filter_list(filters.empty() ? (mixed_pixels ? "paper" : "none") : filters);
  if (!urg) {
    if (mixed_pixels || !options.filters.empty()) {
      raise_input_error("mixed_pixels and filters apply to the URG only, not to sensor 'structured-light'");
    }
    options.structured_light.pipeline = parse_enum_name<StripePipeline>(pipeline);
  }
  if (out_dir) io::check_output_folder(*out_dir, "out_dir");
  const Scene scene = load_scene_yaml(scene_path);
  CartRailResult result;
  {
    py::gil_scoped_release release;
    result = run_cart_rail(scene, options);
  }
  const CartRailRunInfo info{sensor, scene_path};
  write_outputs(out_dir, [&](const std::string& folder) { write_cart_rail_outputs(result, options, info, folder); });
  return json_to_dict(cart_rail_summary_json(result, options, info));
}

}  // namespace

void register_experiments(py::module_& m) {
  m.def("run_rocky_walk", &run_rocky_walk_py, py::arg("scene_path"), py::kw_only(), py::arg("seed") = 1,
        py::arg("sweep") = std::vector<double>{0.0, 0.5, 1.0, 2.0, 4.0}, py::arg("reference") = "map-footholds",
        py::arg("calibrate_attitude") = true, py::arg("calibrate_range") = false, py::arg("mixed_pixels") = false, py::arg("coupling") = true, py::arg("filters") = "", py::arg("map_filter") = "fill",
        py::arg("pose_error_scale") = 1.0, py::arg("out_dir") = py::none(),
        "`stridemap experiment rocky-walk` with the URG: the walking robot along the scene's walk_path with an "
        "imperfect pose, then the pose-error sweep (sweep: factors; [] for none). Defaults as the CLI's for the URG: "
        "h_ref from the map under the stance feet, the IMU biases calibrated on a flat floor first, no range "
        "calibration; with mixed_pixels, the receiver's range-intensity coupling unless coupling=False. Returns summary.json's content "
        "as a dict (docs/experiments.md); out_dir: also write the command's outputs there (an existing folder "
        "must hold only an earlier run's outputs). Deterministic for a seed. Minutes with the full sweep.");
  m.def("run_cart_rail", &run_cart_rail_py, py::arg("scene_path"), py::kw_only(), py::arg("sensor") = "urg",
        py::arg("seed") = 1, py::arg("cell_size_m") = py::none(), py::arg("cells_per_side") = 0,
        py::arg("mixed_pixels") = false, py::arg("coupling") = true, py::arg("filters") = "", py::arg("map_filter") = py::none(),
        py::arg("elevation_rule") = "paper", py::arg("pipeline") = "image", py::arg("out_dir") = py::none(),
        "`stridemap experiment cart-rail`: the sensor ('urg' or 'structured-light') on a cart along the scene's "
        "rail, the map scored against the scene. Defaults per sensor as the CLI's (URG: 10 mm cells, fill; "
        "structured light: 5 mm, cas; with mixed_pixels, the receiver's coupling unless coupling=False). Returns "
        "summary.json's content as a dict; out_dir as for run_rocky_walk.");
}

}  // namespace stridemap::python
