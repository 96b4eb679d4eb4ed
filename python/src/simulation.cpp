// stridemap.Scene and the URG-04LX simulator (sim/): scenes from YAML, and
// simulated raw scans from given poses or along the scene's walk path.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <pybind11/stl.h>

#include "bindings.hpp"
#include "stridemap/config/scene_yaml.hpp"
#include "stridemap/sim/scene.hpp"
#include "stridemap/sim/urg_simulator.hpp"
#include "stridemap/sim/walk_motion.hpp"

namespace stridemap::python {
namespace {

UrgSimOptions sim_options(bool noise, bool systematic_error, bool dropouts) {
  UrgSimOptions options;
  options.enable_noise = noise;
  options.enable_systematic_error = systematic_error;
  options.enable_dropouts = dropouts;
  return options;
}

// Scan k of `poses` from the true pose; the simulator seeds scan k's noise
// from (seed, k), so a seed gives the same scans on every run.
py::array_t<std::uint32_t> simulate(const Scene& scene, const std::vector<TrunkPose>& poses,
                                    const std::vector<double>& times_s, const SensorMount& mount,
                                    const UrgParameters& urg, std::uint64_t seed, const UrgSimOptions& options) {
  UrgSimulator simulator(scene, urg, options, seed);
  const auto beams = static_cast<py::ssize_t>(urg.beam_count());
  py::array_t<std::uint32_t> out({static_cast<py::ssize_t>(poses.size()), beams});
  auto rows = out.mutable_unchecked<2>();
  UrgRawScan raw;
  {
    py::gil_scoped_release release;
    for (std::size_t k = 0; k < poses.size(); ++k) {
      simulator.scan(poses[k], mount, times_s[k], raw);
      for (py::ssize_t i = 0; i < beams; ++i) rows(static_cast<py::ssize_t>(k), i) = raw.values_mm[i];
    }
  }
  return out;
}

py::array_t<std::uint32_t> simulate_urg_scans(const Scene& scene, const py::handle& poses, const py::handle& times_s,
                                              const SensorMount& mount, const UrgParameters& urg, std::uint64_t seed,
                                              bool noise, bool systematic_error, bool dropouts) {
  const auto q = as_float64(poses, "poses");
  const auto t = as_float64(times_s, "times_s");
  if (q.ndim() != 2 || (q.shape(1) != 5 && q.shape(1) != 6)) {
    raise_input_error("poses: expected shape (K, 5) or (K, 6), got " + py::str(py::object(q.attr("shape"))).cast<std::string>());
  }
  if (t.ndim() != 1 || t.shape(0) != q.shape(0)) {
    raise_input_error("times_s: expected one time per pose (" + std::to_string(q.shape(0)) + "), got shape " +
                      py::str(py::object(t.attr("shape"))).cast<std::string>());
  }
  urg.validate();
  std::vector<TrunkPose> trunk;
  std::vector<double> times;
  for (py::ssize_t k = 0; k < q.shape(0); ++k) {
    trunk.push_back(
        pose_from_values(q.data(k, 0), static_cast<std::size_t>(q.shape(1)), 0.0, 0.0, element_name("poses", k)));
    times.push_back(finite_number(t.at(k), element_name("times_s", k)));
  }
  warn_implausible_tilts(q, "poses");
  return simulate(scene, trunk, times, mount, urg, seed, sim_options(noise, systematic_error, dropouts));
}

py::dict simulate_walk(const Scene& scene, const SensorMount& mount, const UrgParameters& urg, std::uint64_t seed,
                       std::optional<double> duration_s, bool noise, bool systematic_error, bool dropouts) {
  urg.validate();
  const WalkMotion motion(scene);
  double end_s = motion.duration_s();
  if (duration_s) {
    if (!(std::isfinite(*duration_s) && *duration_s > 0.0)) {
      raise_input_error("duration_s: expected a positive number of seconds, got " + std::to_string(*duration_s));
    }
    end_s = std::min(end_s, *duration_s);
  }
  const double period = urg.scan_period_s;
  const auto count = static_cast<std::size_t>(std::floor(end_s / period)) + 1;
  std::vector<TrunkPose> poses;
  std::vector<double> times;
  py::array_t<double> pose_array({static_cast<py::ssize_t>(count), py::ssize_t{5}});
  py::array_t<double> time_array(static_cast<py::ssize_t>(count));
  py::array_t<double> h_ref(static_cast<py::ssize_t>(count)), d_z(static_cast<py::ssize_t>(count));
  auto p = pose_array.mutable_unchecked<2>();
  for (std::size_t k = 0; k < count; ++k) {
    const double t = static_cast<double>(k) * period;
    const TrunkPose pose = motion.pose_at(t);
    poses.push_back(pose);
    times.push_back(t);
    const auto i = static_cast<py::ssize_t>(k);
    p(i, 0) = pose.x_m;
    p(i, 1) = pose.y_m;
    p(i, 2) = pose.roll_rad;
    p(i, 3) = pose.pitch_rad;
    p(i, 4) = pose.yaw_rad;
    time_array.mutable_at(i) = t;
    h_ref.mutable_at(i) = pose.reference_elevation_m;
    d_z.mutable_at(i) = pose.height_change_m;
  }
  py::dict d;
  d["times_s"] = time_array;
  d["ranges_mm"] = simulate(scene, poses, times, mount, urg, seed, sim_options(noise, systematic_error, dropouts));
  d["poses"] = pose_array;
  d["reference_elevation_m"] = h_ref;
  d["height_change_m"] = d_z;
  return d;
}

}  // namespace

void register_simulation(py::module_& m) {
  py::class_<Scene>(m, "Scene",
                    "A simulated scene (sim/scene.hpp): a terrain height field, boxes and cylinders, optionally a "
                    "cart rail and a walk path. Read with load_scene or parse_scene (schema: docs/scenes.md).")
      .def("surface_height_at", [](const Scene& s, double x_m, double y_m) {
             return s.surface_height_at(finite_number(x_m, "x_m"), finite_number(y_m, "y_m"));
           }, py::arg("x_m"), py::arg("y_m"), "Highest surface (terrain or object top) at the point [m].")
      .def("max_height_in_rect", &Scene::max_height_in_rect, py::arg("min_x_m"), py::arg("min_y_m"),
           py::arg("max_x_m"), py::arg("max_y_m"), "Highest terrain or object point in the rectangle [m]: a cell's truth.")
      .def_property_readonly("has_walk_path", [](const Scene& s) { return s.walk_path.has_value(); },
                             "Whether the scene has a walk_path section (simulate_walk needs one).")
      .def_property_readonly("has_cart_rail", [](const Scene& s) { return s.cart_rail.has_value(); },
                             "Whether the scene has a cart_rail section.")
      .def_property_readonly("box_count", [](const Scene& s) { return s.boxes.size(); }, "Boxes in the scene.")
      .def_property_readonly("cylinder_count", [](const Scene& s) { return s.cylinders.size(); },
                             "Cylinders in the scene.");
  m.def("load_scene", [](const FilePath& path) { return load_scene_yaml(path); }, py::arg("path"),
        "Reads a scene file. Raises InputError '<file>:<line>: <field>: <what is wrong>'.");
  m.def("parse_scene", &parse_scene_yaml, py::arg("text"), py::arg("source_name") = "<scene>",
        "Parses scene YAML text; source_name stands for the file in messages.");
  m.def("simulate_urg_scans", &simulate_urg_scans, py::arg("scene"), py::arg("poses"), py::arg("times_s"),
        py::kw_only(), py::arg("mount") = SensorMount{}, py::arg("urg") = UrgParameters{}, py::arg("seed") = 1,
        py::arg("noise") = true, py::arg("systematic_error") = true, py::arg("dropouts") = true,
        "Simulated URG-04LX raw scans (uint32 millimetres, error codes below 20 kept), shape (K, beams), one per "
        "TRUE pose (K, 5) or (K, 6) at times_s (K,). Deterministic for a seed: scan k's noise depends on (seed, k).");
  m.def("simulate_walk", &simulate_walk, py::arg("scene"), py::kw_only(), py::arg("mount") = SensorMount{},
        py::arg("urg") = UrgParameters{}, py::arg("seed") = 1, py::arg("duration_s") = py::none(),
        py::arg("noise") = true, py::arg("systematic_error") = true, py::arg("dropouts") = true,
        "The walking robot along the scene's walk_path (InputError without one), one URG scan per scan period up "
        "to duration_s (default: the whole walk). Returns a dict: times_s (K,), ranges_mm (K, beams) uint32, "
        "poses (K, 5) true (x_m, y_m, roll_rad, pitch_rad, yaw_rad), reference_elevation_m (K,), height_change_m "
        "(K,): everything Pipeline.add_urg_scans takes.");
}

}  // namespace stridemap::python
