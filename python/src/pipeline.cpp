// stridemap.Pipeline: the library's one entry point (MappingPipeline) fed
// from NumPy. Every array is checked here, naming the argument, before the
// library sees it; the library's own InputErrors pass through unchanged.
#include <optional>
#include <string>
#include <unordered_map>

#include <pybind11/stl.h>

#include "bindings.hpp"
#include "feed/scan_feed.hpp"
#include "stridemap/config/mapper_config.hpp"
#include "stridemap/core/map_resume.hpp"
#include "stridemap/core/stance_height.hpp"
#include "stridemap/pipeline/mapping_pipeline.hpp"

namespace stridemap::python {
namespace {

py::dict scan_stats_dict(const ScanStats& s) {
  py::dict d;
  d["beams"] = s.beams;
  d["integrated"] = s.integrated;
  d["first"] = s.first;
  d["plausible"] = s.plausible;
  d["implausible"] = s.implausible;
  d["replaced"] = s.replaced;
  d["invalid_range"] = s.invalid_range;
  d["invalid_beam"] = s.invalid_beam;
  d["outside_map"] = s.outside_map;
  d["pose_rejected"] = s.pose_rejected;
  d["time_rejected"] = s.time_rejected;
  d["cells_reset_by_move"] = s.cells_reset_by_move;
  return d;
}

py::dict outcome_dict(const ScanOutcome& outcome) {
  py::dict d = scan_stats_dict(outcome.stats);
  d["reached_mapper"] = outcome.integrated;
  return d;
}

// The settings a map file records (io/mapper_config.hpp's sections), as
// the CLI's ScanMapper::pipeline_options spreads them the other way.
MapperConfig mapper_config_of(const PipelineOptions& options) {
  MapperConfig config;
  config.mount = options.mount;
  config.mapper = options.mapper;
  config.fill = options.map_filter.fill;
  config.calibration = options.calibration;
  config.foothold = options.foothold;
  config.visibility = options.visibility;
  config.height_fusion = options.height_fusion;
  return config;
}

// Scans the mapper turned down are not an error of the call (a stream may
// repeat one), but a silent count would read as success: said as a warning.
void warn_rejected(std::size_t offered, std::size_t mapped, std::size_t stale, std::size_t bad_pose,
                   std::size_t unfit, std::optional<py::ssize_t> first_stale) {
  if (stale + bad_pose + unfit == 0) return;
  std::string message = "add_urg_scans: " + std::to_string(stale + bad_pose + unfit) + " of " +
                        std::to_string(offered) + " scans were not mapped (" + std::to_string(mapped) + " were): " +
                        std::to_string(stale) + " with a time not after the last mapped scan's";
  if (first_stale) message += " (the first at row " + std::to_string(*first_stale) + "; times_s must increase)";
  message += ", " + std::to_string(bad_pose) + " with a bad pose, " + std::to_string(unfit) +
             " that do not fit the sensor";
  if (PyErr_WarnEx(PyExc_RuntimeWarning, message.c_str(), 1) != 0) throw py::error_already_set();
}

class Pipeline;

// The live pipelines by the map they build, so that Map.save of
// `pipeline.map` records the pipeline's settings and last pose: a bare map
// file cannot be resumed (io/map_resume_check.hpp). A Map taken from a
// pipeline keeps it alive, so an entry outlives every such Map. Touched with
// the GIL held only.
std::unordered_map<const ElevationMap*, const Pipeline*>& live_pipelines() {
  static std::unordered_map<const ElevationMap*, const Pipeline*> pipelines;
  return pipelines;
}

// fused_heights=True is the options' height_fusion.enabled.
PipelineOptions with_fused_heights(PipelineOptions options, bool fused_heights) {
  options.height_fusion.enabled = options.height_fusion.enabled || fused_heights;
  return options;
}

class Pipeline {
 public:
  Pipeline(const PipelineOptions& options, const ElevationMap* resume_from, bool fused_heights)
      : pipeline_(with_fused_heights(options, fused_heights)), feed_(pipeline_) {
    if (resume_from) resume_from_map(pipeline_.mapper(), *resume_from);
    live_pipelines()[&pipeline_.mapper().map()] = this;
  }
  ~Pipeline() { live_pipelines().erase(&pipeline_.mapper().map()); }
  Pipeline(const Pipeline&) = delete;
  Pipeline& operator=(const Pipeline&) = delete;

  /// What the CLI's map file records of its run (live/map_report.cpp).
  io::MapFileMetadata file_metadata(const std::string& created_by) const {
    io::MapFileMetadata metadata = io::map_file_metadata(mapper_config_of(pipeline_.options()), created_by);
    metadata.last_scan_time_s = pipeline_.mapper().last_scan_time_s();
    metadata.last_pose = pipeline_.mapper().last_pose();
    return metadata;
  }

  py::dict add_urg_scan(const py::handle& ranges, double time_s, const py::handle& pose, const std::string& units,
                        std::optional<int> first_step, int cluster, double reference_elevation_m,
                        double height_change_m) {
    const TrunkPose p = pose_from_object(pose, reference_elevation_m, height_change_m, "pose");
    finite_number(time_s, "time_s");
    const RangeUnits u = range_units(units);
    const auto values = range_values(ranges, "ranges", u);
    if (values.ndim() != 1) raise_input_error("ranges: expected one scan (1-D), got shape " + shape_text(values));
    return outcome_dict(
        feed_.add_urg(values.data(), static_cast<std::size_t>(values.shape(0)), u, time_s, first_step, cluster, p));
  }

  std::size_t add_urg_scans(const py::handle& ranges, const py::handle& times_s, const py::handle& poses,
                            const std::string& units, const py::handle& reference_elevation_m,
                            const py::handle& height_change_m) {
    const py::array rows = as_array(ranges, "ranges");
    const auto r = as_float64(rows, "ranges");  // shape only; values are checked per row
    const auto t = as_float64(times_s, "times_s");
    const auto q = as_float64(poses, "poses");
    if (r.ndim() != 2) raise_input_error("ranges: expected a 2-D array (scans x values), got " + std::to_string(r.ndim()) + " dimensions");
    const py::ssize_t k = r.shape(0);
    if (t.ndim() != 1 || t.shape(0) != k) {
      raise_input_error("times_s: expected one time per scan (" + std::to_string(k) + "), got shape " + shape_text(t));
    }
    if (q.ndim() != 2 || q.shape(0) != k || (q.shape(1) != 5 && q.shape(1) != 6)) {
      raise_input_error("poses: expected shape (" + std::to_string(k) + ", 5) or (" + std::to_string(k) +
                        ", 6), got " + shape_text(q));
    }
    // Before any scan is mapped: with warnings as errors nothing changes.
    warn_implausible_tilts(q, "poses");
    const auto h_ref = per_scan(reference_elevation_m, k, "reference_elevation_m");
    const auto d_z = per_scan(height_change_m, k, "height_change_m");
    if (k == 0) return 0;
    UrgBatch batch;
    batch.scans = static_cast<std::size_t>(k);
    // One dtype for every row: checked once, naming the first row as a
    // row-by-row check would.
    batch.units = range_units(units);
    check_range_dtype(rows, element_name("ranges", 0), batch.units);
    batch.ranges = r.data();
    batch.values_per_scan = static_cast<std::size_t>(r.shape(1));
    batch.times_s = t.data();
    batch.poses = q.data();
    batch.pose_values = static_cast<std::size_t>(q.shape(1));
    batch.reference_elevation_m = h_ref ? h_ref->data() : nullptr;
    batch.height_change_m = d_z ? d_z->data() : nullptr;
    const UrgBatchCounts c = feed_.add_urg_batch(batch);
    std::optional<py::ssize_t> first_stale;
    if (c.first_stale) first_stale = static_cast<py::ssize_t>(*c.first_stale);
    warn_rejected(batch.scans, c.mapped, c.stale, c.bad_pose, c.unfit, first_stale);
    return c.mapped;
  }

  py::dict add_points(const py::handle& points, const py::handle& sigma_m, double time_s, const py::handle& pose,
                      double reference_elevation_m, double height_change_m) {
    const TrunkPose p = pose_from_object(pose, reference_elevation_m, height_change_m, "pose");
    const auto xyz = as_float64(points, "points");
    if (xyz.ndim() != 2 || xyz.shape(1) != 3) raise_input_error("points: expected shape (N, 3), got " + shape_text(xyz));
    const auto n = xyz.shape(0);
    const auto sigma = as_float64(sigma_m, "sigma_m");
    if (!(sigma.ndim() == 0 || (sigma.ndim() == 1 && sigma.shape(0) == n))) {
      raise_input_error("sigma_m: expected one sigma per point (" + std::to_string(n) + ") or one for all, got shape " +
                        shape_text(sigma));
    }
    finite_number(time_s, "time_s");
    return outcome_dict(
        feed_.add_points(xyz.data(), static_cast<std::size_t>(n), sigma.data(), sigma.ndim() == 0, time_s, p));
  }

  py::dict add_stripe(const py::handle& pixels, std::optional<double> time_s, const py::handle& pose,
                      double reference_elevation_m, double height_change_m) {
    const TrunkPose p = pose_from_object(pose, reference_elevation_m, height_change_m, "pose");
    const auto uv = as_float64(pixels, "pixels");
    if (uv.ndim() != 2 || uv.shape(1) != 2) raise_input_error("pixels: expected shape (N, 2) of (u_px, v_px), got " + shape_text(uv));
    if (time_s) finite_number(*time_s, "time_s");
    return outcome_dict(feed_.add_stripe(uv.data(), static_cast<std::size_t>(uv.shape(0)), time_s, p));
  }

  MappingPipeline& pipeline() { return pipeline_; }
  const MappingPipeline& pipeline() const { return pipeline_; }

  py::dict stance_height(const py::handle& feet, double sole_radius_m, double min_known_share, double gate_sigmas,
                         double depth_sigma_m) const {
    if (pipeline_.height_fusion() == nullptr) {
      raise_input_error("stance_height: the pipeline keeps no fused heights; make it with fused_heights=True");
    }
    const auto a = as_float64(feet, "feet");
    if (a.ndim() != 2 || a.shape(1) != 3) {
      raise_input_error("feet: expected shape (N, 3) of (x_m, y_m, depth_m), got " + shape_text(a));
    }
    std::array<StanceFoot, StanceHeight::kMaxFeet> stance{};
    const auto n = static_cast<std::size_t>(a.shape(0));
    if (n > stance.size()) {
      raise_input_error("feet: " + std::to_string(n) + " feet given, at most " + std::to_string(stance.size()));
    }
    for (std::size_t k = 0; k < n; ++k) {
      const auto i = static_cast<py::ssize_t>(k);
      stance[k] = {a.at(i, 0), a.at(i, 1), a.at(i, 2)};
    }
    StanceHeightOptions options;
    options.sole_radius_m = sole_radius_m;
    options.min_known_share = min_known_share;
    options.gate_sigmas = gate_sigmas;
    options.depth_sigma_m = depth_sigma_m;
    const ElevationMap& map = pipeline_.mapper().map();
    const StanceHeight h = StanceHeightReader(map, options).read(map, std::span<const StanceFoot>(stance.data(), n));
    py::dict d;
    d["trunk_z_m"] = h.trunk_z_m;
    d["variance_m2"] = h.variance_m2;
    d["feet_read"] = h.feet_read;
    d["feet_used"] = h.feet_used;
    py::list used, ground;
    for (std::size_t k = 0; k < n; ++k) {
      used.append(h.feet[k].used);
      ground.append(h.feet[k].ground_m);
    }
    d["used"] = used;
    d["ground_m"] = ground;
    return d;
  }

  py::dict stats() const {
    const PipelineStats s = pipeline_.stats();
    py::dict d;
    d["scans"] = s.scans;
    d["integrated"] = s.integrated;
    d["rejected"] = s.rejected;
    d["beams_valid"] = s.beams.valid;
    d["beams_error_codes"] = s.beams.error_codes;
    d["beams_beyond_max_range"] = s.beams.beyond_max_range;
    d["points"] = s.points.points;
    d["points_converted"] = s.points.converted;
    d["points_not_finite"] = s.points.not_finite;
    d["stripe_pixels"] = s.stripe.pixels;
    d["stripe_converted"] = s.stripe.converted;
    const MapperTotals& t = pipeline_.mapper().totals();
    d["mapper_scans"] = t.scans;
    d["scans_rejected_for_pose"] = t.scans_rejected_for_pose;
    d["scans_rejected_for_time"] = t.scans_rejected_for_time;
    d["mapper_beams"] = t.beams;
    d["mapper_integrated"] = t.integrated;
    d["invalid_range"] = t.invalid_range;
    d["invalid_beam"] = t.invalid_beam;
    d["outside_map"] = t.outside_map;
    d["implausible"] = t.implausible;
    return d;
  }

 private:
  static std::string shape_text(const py::array& a) { return py::str(py::object(a.attr("shape"))).cast<std::string>(); }

  // One finite value per scan, or none (every scan's 0). Checked whole
  // before any scan is mapped.
  static std::optional<py::array_t<double, py::array::c_style>> per_scan(const py::handle& values, py::ssize_t k,
                                                                         const std::string& argument) {
    if (values.is_none()) return std::nullopt;
    auto a = as_float64(values, argument);
    if (a.ndim() != 1 || a.shape(0) != k) {
      raise_input_error(argument + ": expected one value per scan (" + std::to_string(k) + "), got shape " + shape_text(a));
    }
    for (py::ssize_t i = 0; i < k; ++i) finite_value(a.at(i), {argument.c_str(), i});
    return a;
  }

  // units='mm' takes the sensor's integers, units='m' floats: a mix-up
  // would map millimetres as kilometres, or the reverse.
  static void check_range_dtype(const py::array& array, const std::string& argument, RangeUnits units) {
    const char kind = array.dtype().kind();
    if (units == RangeUnits::mm && kind != 'i' && kind != 'u') {
      throw py::type_error(argument + ": units='mm' takes the sensor's raw integer millimetres, got dtype " +
                           dtype_text(array) + "; pass units='m' for ranges in metres");
    }
    if (units == RangeUnits::m && kind != 'f') {
      throw py::type_error(argument + ": units='m' takes floating-point metres, got dtype " + dtype_text(array) +
                           "; pass units='mm' for raw integer millimetres");
    }
  }

  static std::string dtype_text(const py::array& a) { return py::str(a.dtype()).cast<std::string>(); }

  // One scan's ranges as float64, its dtype checked against the units first.
  static py::array_t<double, py::array::c_style> range_values(const py::handle& ranges, const std::string& argument,
                                                              RangeUnits units) {
    const py::array array = as_array(ranges, argument);
    check_range_dtype(array, argument, units);
    return as_float64(array, argument);
  }

  MappingPipeline pipeline_;
  ScanFeed feed_;  // every add_*'s per-scan work, after the checks only the binding can make
};

}  // namespace

std::optional<io::MapFileMetadata> pipeline_map_metadata(const ElevationMap& map, const std::string& created_by) {
  const auto it = live_pipelines().find(&map);
  if (it == live_pipelines().end()) return std::nullopt;
  return it->second->file_metadata(created_by);
}

const ElevationMap& layers_current(const ElevationMap& map) {
  const auto it = live_pipelines().find(&map);
  if (it != live_pipelines().end()) (void)it->second->pipeline().map();
  return map;
}

void register_pipeline(py::module_& m) {
  const char* pose_doc =
      "pose: 5 numbers (x_m, y_m, roll_rad, pitch_rad, yaw_rad; the paper's model: the sensor at mount.height_m "
      "+ reference_elevation_m + height_change_m) or 6 (x_m, y_m, z_m, roll_rad, pitch_rad, yaw_rad; a 6-DoF "
      "state, the mount applied rigidly). Positive pitch is nose down, positive roll left side up.";
  py::class_<Pipeline>(m, "Pipeline",
                       "The mapping pipeline (pipeline/mapping_pipeline.hpp): scans and poses in, an elevation map "
                       "out. Every add_* returns the mapper's account of the scan as a dict.")
      .def(py::init([](const PipelineOptions& options, const ElevationMap* resume_from, bool fused_heights) {
             return std::make_unique<Pipeline>(options, resume_from, fused_heights);
           }),
           py::arg("options") = PipelineOptions{}, py::arg("resume_from") = nullptr, py::kw_only(),
           py::arg("fused_heights") = false,
           "Raises InputError for invalid options. resume_from: a Map (e.g. load_map(path).map) to go on mapping "
           "from; its grid must be the options' (InputError otherwise). The map is copied. fused_heights: also "
           "keep the layers fused_elevation and fused_variance (core/height_fusion.hpp), from which "
           "stance_height() reads the robot's own height; the paper's layers stay as they are (the same as a "
           "config's height_fusion.enabled, read by PipelineOptions.from_config).")
      .def("add_urg_scan", &Pipeline::add_urg_scan, py::arg("ranges"), py::arg("time_s"), py::arg("pose"),
           py::kw_only(), py::arg("units") = "mm", py::arg("first_step") = py::none(), py::arg("cluster") = 1,
           py::arg("reference_elevation_m") = 0.0, py::arg("height_change_m") = 0.0,
           (std::string("One URG-04LX scan, integrated now. ranges: 1-D; units='mm' (default): the raw integer "
                        "values the sensor sends, error codes below DMIN kept; units='m': floats in metres, NaN/inf/0 "
                        "for no echo. One value per step from first_step (default the sensor's AMIN). time_s: the "
                        "scan's time [s], later than the last scan's. ") +
            pose_doc + " Raises InputError/TypeError naming the argument.")
               .c_str())
      .def("add_urg_scans", &Pipeline::add_urg_scans, py::arg("ranges"), py::arg("times_s"), py::arg("poses"),
           py::kw_only(), py::arg("units") = "mm", py::arg("reference_elevation_m") = py::none(),
           py::arg("height_change_m") = py::none(),
           "K scans at once: ranges (K, values), times_s (K,), poses (K, 5) or (K, 6) as for add_urg_scan; "
           "reference_elevation_m, height_change_m: None or (K,). Returns how many scans were mapped (one the "
           "scan filters hold is mapped by the next call or finish()); a RuntimeWarning counts the scans rejected "
           "and says why (times not increasing, a bad pose, not the sensor's shape).")
      .def("add_points", &Pipeline::add_points, py::arg("points"), py::arg("sigma_m"), py::arg("time_s"),
           py::arg("pose"), py::kw_only(), py::arg("reference_elevation_m") = 0.0, py::arg("height_change_m") = 0.0,
           "Sensor 'points': points (N, 3) in the sensor frame [m] (x ahead, y left, z up before the mount's "
           "pitch) with a height sigma each (N,) or one for all [m]. Non-finite points are counted, not used.")
      .def("add_stripe", &Pipeline::add_stripe, py::arg("pixels"), py::arg("time_s"), py::arg("pose"), py::kw_only(),
           py::arg("reference_elevation_m") = 0.0, py::arg("height_change_m") = 0.0,
           "Sensor 'structured-light': one frame's stripe pixels (N, 2) of (u_px, v_px); time_s may be None.")
      .def("stance_height", &Pipeline::stance_height, py::arg("feet"), py::kw_only(), py::arg("sole_radius_m") = 0.02,
           py::arg("min_known_share") = 0.5, py::arg("gate_sigmas") = 2.5, py::arg("depth_sigma_m") = 0.002,
           "The trunk's height above the map's zero (h_ref + height_change_m of the next scan's pose) from where "
           "the stance feet stand (core/stance_height.hpp; needs fused_heights=True). feet: (N, 3) of (x_m, y_m, "
           "depth_m), N <= 8: each sole's centre in the map frame and its depth below the trunk's reference point, "
           "from the robot's kinematics and pose. Returns {'trunk_z_m' (NaN when no foot stands on known cells), "
           "'variance_m2', 'feet_read', 'feet_used', 'used' (per foot), 'ground_m' (per foot, NaN when not read)}. "
           "h_ref = trunk_z_m - height_change_m.")
      .def("finish", [](Pipeline& p) { return outcome_dict(p.pipeline().finish()); },
           "Ends the stream: the scan the scan-sequence filter holds is integrated.")
      .def("apply_map_filter",
           [](Pipeline& p) {
             const MapFilterResult r = p.pipeline().apply_map_filter();
             py::dict d;
             d["filled"] = r.filled;
             d["cas_removed"] = r.cas_removed;
             return d;
           },
           "Runs the options' map filter on the map being built; returns {'filled', 'cas_removed'}.")
      .def("filtered_map", [](Pipeline& p) { return p.pipeline().filtered_map(); },
           "A copy of the map with the map filter applied; the map being built is unchanged.")
      .def_property_readonly(
          "map",
          [](Pipeline& p) -> ElevationMap& {
            (void)p.pipeline().map();  // the foothold layers, computed when read
            return p.pipeline().mapper().map();
          },
          py::return_value_policy::reference_internal,
          "The map being built (not a copy: it keeps this pipeline alive, and its views show later scans; the "
          "foothold layers are computed when the map is read, so a view of one held across scans shows them as "
          "of the last read: pipeline.map, or any Map method).")
      .def(
          "save",
          [](const Pipeline& p, const FilePath& path, const std::string& created_by, bool overwrite_other_files) {
            io::save_map_file(path, p.pipeline().map(), p.file_metadata(created_by), {overwrite_other_files});
          },
          py::arg("path"), py::kw_only(), py::arg("created_by") = kPipelineCreatedBy,
          py::arg("overwrite_other_files") = false,
          "Writes the map being built as a map file (.smap, docs/map_file.md) with what the CLI's `map` records: "
          "the mount, the configuration (the options' mapper settings as JSON), the last scan's pose and time; "
          "so that `stridemap map --resume` and `live --resume` can go on from it with the same settings. "
          "pipeline.map.save(path) does the same. Replaces an existing map file only, as Map.save.")
      .def_property_readonly("options", [](Pipeline& p) { return p.pipeline().options(); }, "A copy of the options.")
      .def_property_readonly(
          "last_scan_time_s", [](Pipeline& p) { return p.pipeline().mapper().last_scan_time_s(); },
          "Time of the last scan the mapper accepted, or None.")
      .def_property_readonly("stats", &Pipeline::stats,
                             "Counts since construction: scans offered and integrated, beams and points by "
                             "outcome, the mapper's totals.");
}

}  // namespace stridemap::python
