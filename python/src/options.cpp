// The option structs as Python classes: plain attributes in SI units with
// the C++ defaults (pipeline/pipeline_options.hpp), enums as their CLI
// names ("urg", "fill", "paper", ...), and a config file read like the CLI's.
#include <string>
#include <vector>

#include <pybind11/stl.h>

#include "bindings.hpp"
#include "option_fields.hpp"
#include "stridemap/config/mapper_config.hpp"
#include "stridemap/config/structured_light_config.hpp"
#include "stridemap/core/map_filter.hpp"
#include "stridemap/core/map_update.hpp"
#include "stridemap/pipeline/pipeline_options.hpp"
#include "stridemap/preprocess/scan_filter_registry.hpp"

namespace stridemap::python {
namespace {

void register_mount(py::module_& m) {
  py::class_<SensorMount> mount(m, "SensorMount",
                          "Where the range sensor sits on the trunk (core/pose.hpp): translation (forward_offset_m, "
                          "lateral_offset_m, height_m) and rotation Rz(yaw) Ry(pitch) Rx(roll). Defaults: the "
                          "paper's Messor mount, 0.26 m high, pitched 35 deg down.");
  mount.def_readwrite("height_m", &SensorMount::height_m, "Sensor origin above the trunk reference point [m].")
      .def_readwrite("pitch_rad", &SensorMount::pitch_rad, "Fixed pitch towards the ground (alpha) [rad].")
      .def_readwrite("forward_offset_m", &SensorMount::forward_offset_m, "Ahead of the trunk reference point [m].")
      .def_readwrite("lateral_offset_m", &SensorMount::lateral_offset_m, "Left of the trunk reference point [m].")
      .def_readwrite("roll_rad", &SensorMount::roll_rad, "Roll about the sensor's X axis, after alpha [rad].")
      .def_readwrite("yaw_rad", &SensorMount::yaw_rad, "Yaw relative to the trunk, before alpha [rad].");
  // Positional too, in the order above: a mount is often written as its
  // numbers, SensorMount(0.26, 0.61).
  add_field_init_and_repr<true>(mount, "A mount: any field by keyword (or positionally in the order height_m, "
                                       "pitch_rad, forward_offset_m, lateral_offset_m, roll_rad, yaw_rad), in "
                                       "metres and radians; the others keep their defaults.");
}

void register_urg(py::module_& m) {
  py::class_<UrgParameters> urg(m, "UrgParameters",
                            "The URG-04LX's geometry and limits as it reports them (SCIP PP). Defaults: steps "
                            "44..725 of 1024, front 384, 20 mm to 5.6 m, 0.1 s per scan (682 beams).");
  urg.def_readwrite("first_step", &UrgParameters::first_step, "AMIN: first measurable step.")
      .def_readwrite("last_step", &UrgParameters::last_step, "AMAX: last measurable step.")
      .def_readwrite("front_step", &UrgParameters::front_step, "AFRT: the step straight ahead.")
      .def_readwrite("steps_per_turn", &UrgParameters::steps_per_turn, "ARES: steps per 360 deg.")
      .def_readwrite("min_range_m", &UrgParameters::min_range_m, "DMIN: raw values below are error codes [m].")
      .def_readwrite("max_range_m", &UrgParameters::max_range_m, "DMAX: raw values above are invalid [m].")
      .def_readwrite("scan_period_s", &UrgParameters::scan_period_s, "Time of one turn [s].")
      .def_property_readonly("beam_count", &UrgParameters::beam_count, "Beams from first_step to last_step.")
      .def("validate", &UrgParameters::validate, "Raises InputError naming a field that does not fit the others.");
  add_field_init_and_repr(urg, "The URG-04LX's defaults, with any field given by keyword.");
}

void register_update(py::module_& m) {
  py::class_<UpdateOptions> update(m, "UpdateOptions", "The map update rule (eq. 9, 10; core/map_update.hpp).");
  update.def_readwrite("certainty_increment", &UpdateOptions::certainty_increment,
                     "a of eq. (9): certainty per plausible measurement.")
      .def_readwrite("certainty_max", &UpdateOptions::certainty_max, "The certainty stops growing here.")
      .def_readwrite("max_pitch_error_rad", &UpdateOptions::max_pitch_error_rad, "Trunk pitch error bound [rad].")
      .def_readwrite("max_roll_error_rad", &UpdateOptions::max_roll_error_rad, "Trunk roll error bound [rad].")
      .def_readwrite("max_mount_pitch_error_rad", &UpdateOptions::max_mount_pitch_error_rad,
                     "Mount pitch error bound [rad].")
      .def_readwrite("use_turning_term", &UpdateOptions::use_turning_term, "Add the turning travel of Fig. 10.")
      .def_property(
          "elevation_rule", [](const UpdateOptions& o) { return std::string(name(o.elevation_rule)); },
          [](UpdateOptions& o, const std::string& text) { o.elevation_rule = parse_enum_name<ElevationRule>(text); },
          "'paper' (eq. 10: the highest reading wins) or 'gated'.")
      .def_readwrite("replace_after_contradictions", &UpdateOptions::replace_after_contradictions,
                     "Gated rule: contradicting readings in a row that replace a cell.");
  add_field_init_and_repr(update, "The paper's rule, with any field given by keyword.");
}

PipelineOptions options_from_config(const FilePath& path, const std::string& sensor) {
  const MapperConfig config = load_mapper_config(path);
  PipelineOptions options;
  options.sensor = parse_sensor_kind(sensor);
  options.mount = config.mount;
  options.mapper = config.mapper;
  options.map_filter.fill = config.fill;
  options.calibration = config.calibration;
  options.height_fusion = config.height_fusion;
  return options;
}

void register_pipeline_options(py::module_& m) {
  py::class_<PipelineOptions> options(m, "PipelineOptions",
                              "Everything that configures a Pipeline (pipeline/pipeline_options.hpp). Defaults: a "
                              "URG-04LX on the paper's Messor mount, no scan filters, a 100 x 100 map of 10 mm "
                              "cells following the robot, the paper's update rule, the fill-in (eq. 11).");
  options.def_static("from_config", &options_from_config, py::arg("path"), py::arg("sensor") = "urg",
                  "Options from a mapper configuration file (YAML, docs/config.md), as the CLI's --config reads "
                  "it: mount, map, update rule, fill-in, range calibration, height_fusion. Raises InputError "
                  "'<file>:<line>: <field>: <what is wrong>'.")
      .def_property(
          "sensor", [](const PipelineOptions& o) { return std::string(sensor_kind_name(o.sensor)); },
          [](PipelineOptions& o, const std::string& text) { o.sensor = parse_sensor_kind(text); },
          "'urg', 'structured-light' or 'points'.")
      .def_readwrite("mount", &PipelineOptions::mount, "The SensorMount.")
      .def_property(
          "foothold_update_every_scan", [](const PipelineOptions& o) { return o.foothold.update_every_scan; },
          [](PipelineOptions& o, bool every_scan) { o.foothold.update_every_scan = every_scan; },
          "Refresh the foothold layers after every scan (True), or when the map is read (False, the default: "
          "pipeline.map, Pipeline.save); the same values either way (docs/foothold.md).")
      .def_readwrite("urg", &PipelineOptions::urg, "UrgParameters of the scans (sensor 'urg').")
      .def_property(
          "cells_per_side", [](const PipelineOptions& o) { return o.mapper.grid.cells_per_side; },
          [](PipelineOptions& o, int n) { o.mapper.grid.cells_per_side = n; }, "N of the N x N map window.")
      .def_property(
          "cell_size_m", [](const PipelineOptions& o) { return o.mapper.grid.cell_size_m; },
          [](PipelineOptions& o, double s) { o.mapper.grid.cell_size_m = s; }, "Edge of a cell [m].")
      .def_property(
          "follow_robot", [](const PipelineOptions& o) { return o.mapper.follow_robot; },
          [](PipelineOptions& o, bool f) { o.mapper.follow_robot = f; },
          "Re-centre the window on the robot before each scan (off: a fixed window around the origin).")
      .def_property(
          "window_ahead_m", [](const PipelineOptions& o) { return o.mapper.window_ahead_m; },
          [](PipelineOptions& o, double a) { o.mapper.window_ahead_m = a; },
          "Window centre ahead of the trunk along the heading [m].")
      .def_property(
          "reject_stale_scans", [](const PipelineOptions& o) { return o.mapper.reject_stale_scans; },
          [](PipelineOptions& o, bool r) { o.mapper.reject_stale_scans = r; },
          "Refuse a scan whose time is not later than the last one's.")
      .def_property(
          "update", [](PipelineOptions& o) -> UpdateOptions& { return o.mapper.update; },
          [](PipelineOptions& o, const UpdateOptions& u) { o.mapper.update = u; }, "The UpdateOptions.",
          py::return_value_policy::reference_internal)
      .def_property(
          "filters", [](const PipelineOptions& o) { return scan_filter_list_name(o.filters); },
          [](PipelineOptions& o, const std::string& names) { o.filters = parse_scan_filter_list(names); },
          ("Scan filters in order, comma separated: " + scan_filter_choices() + ". URG only.").c_str())
      .def_property(
          "map_filter", [](const PipelineOptions& o) { return std::string(map_filter_name(o.map_filter.filter)); },
          [](PipelineOptions& o, const std::string& text) { o.map_filter.filter = parse_map_filter(text); },
          "What apply_map_filter() runs: 'fill' (eq. 11), 'cas' or 'none'.")
      .def_property(
          "sigma_scale", [](const PipelineOptions& o) { return o.points.sigma_scale; },
          [](PipelineOptions& o, double s) { o.points.sigma_scale = s; },
          "Sensor 'points': Delta z of a point = sigma_scale x its sigma.")
      .def(
          "load_structured_light_config",
          [](PipelineOptions& o, const FilePath& path) {
            o.structured_light = load_structured_light_config(path).parameters;
          },
          py::arg("path"),
          "Camera and light sheet of sensor 'structured-light' from a configuration file "
          "(docs/structured_light.md); its mount section is not used: `mount` places the sensor.");
  add_field_init_and_repr(options, "The defaults, with any field given by keyword: "
                                   "PipelineOptions(cells_per_side=200, filters='paper').");
}

}  // namespace

void register_options(py::module_& m) {
  register_mount(m);
  register_urg(m);
  register_update(m);
  register_pipeline_options(m);
  // From the registry, so a filter registered in C++ is listed too.
  m.def(
      "scan_filters",
      [] {
        py::list filters;
        for (const ScanFilterRegistration& filter : registered_scan_filters()) {
          py::dict parameters;
          for (const ScanFilterParameter& p : filter.parameters) parameters[py::str(p.name)] = p.default_value;
          filters.append(py::dict(py::arg("name") = filter.name, py::arg("description") = filter.description,
                                  py::arg("parameters") = parameters));
        }
        for (const ScanFilterSet& set : registered_scan_filter_sets()) {
          filters.append(py::dict(py::arg("name") = set.name, py::arg("description") = set.description,
                                  py::arg("members") = set.members));
        }
        return filters;
      },
      "The names PipelineOptions.filters takes, in registration order: each filter as {'name', 'description', "
      "'parameters' (defaults)}, then each set ('paper', 'urg') as {'name', 'description', 'members'}.");
}

}  // namespace stridemap::python
