// The cart-rail run with the structured-light sensor: per pose a camera
// frame, either rendered and searched by the detector (the full path) or
// taken from the geometric simulator's truth, then eq. (1), (5) and (8) and
// the same update rule as the laser.
#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

#include "cart_rail_internal.hpp"
#include "stridemap/core/error.hpp"
#include "stridemap/core/sensor_transform.hpp"
#include "stridemap/experiments/map_evaluation.hpp"
#include "stridemap/sensors/structured_light_report.hpp"

namespace stridemap {
namespace {

// What a false detection puts in the map: whether its point lies off every
// surface. A pixel without a point (its ray misses the sheet) adds none.
bool off_every_surface(const io::StripeColumnDetection& d, const StructuredLightModel& model, const TrunkPose& pose,
                       const Scene& scene, double off_surface_m) {
  Eigen::Vector3d camera_point;
  if (model.back_project(d.u_px, d.v_px, camera_point) != StripePointStatus::valid) return false;
  const Eigen::Vector3d world =
      sensor_point_to_map(camera_to_sensor_frame(camera_point), pose, model.parameters().mount);
  const double r = off_surface_m;
  const SurfaceSpan span = surface_span(scene, world.x() - r, world.y() - r, world.x() + r, world.y() + r);
  return world.z() > span.high_m + r || world.z() < std::min(span.low_m, span.high_m) - r;
}

// Whether a detection lies on laser light in the rendered frame: within the
// row tolerance of a peak of its column's noise-free laser signal that
// clears the noise. A peak, not any lit pixel, so that the blurred flank of
// the true stripe a few rows off does not excuse a detection there. The
// truth of the image, not of the sheet: it also names the laser's light
// at an occlusion edge or on a box's edge lit by the sheet's tail.
bool on_laser_light(const io::StripeColumnDetection& d, const StructuredLightImageRenderer& renderer,
                    const StructuredLightRailOptions& options) {
  const int u = static_cast<int>(std::floor(d.u_px));
  const int first = static_cast<int>(std::ceil(d.v_px - options.row_tolerance_px - 0.5));
  const int last = static_cast<int>(std::floor(d.v_px + options.row_tolerance_px - 0.5));
  for (int v = first; v <= last; ++v) {
    const double signal = renderer.laser_signal_dn(u, v);
    if (signal >= renderer.laser_signal_dn(u, v - 1) && signal >= renderer.laser_signal_dn(u, v + 1) &&
        renderer.laser_signal_to_noise(u, v) >= options.laser_light_min_snr) {
      return true;
    }
  }
  return false;
}

// Scores one frame's detections against the truth; returns the sum of the
// squared row errors of the correct ones.
double tally_frame(const io::StripeDetection& detection, const StructuredLightFrameTruth& truth,
                   const StructuredLightRailOptions& options, const StructuredLightModel& model, const TrunkPose& pose,
                   const Scene& scene, const StructuredLightImageRenderer& renderer, StripeTally& tally) {
  double sum_sq = 0.0;
  for (std::size_t i = 0; i < truth.columns.size(); ++i) {
    const StripeColumnTruth& t = truth.columns[i];
    const bool visible = t.label == StripeColumnLabel::visible;
    tally.truth_visible += visible;
    if (i >= detection.columns.size()) continue;
    const io::StripeColumnDetection& d = detection.columns[i];
    if (!d.found || d.confidence < options.min_confidence) continue;
    ++tally.detected;
    const double error = d.v_px - t.v_px;
    if (visible && std::abs(error) <= options.row_tolerance_px) {
      ++tally.correct;
      sum_sq += error * error;
    } else {
      ++tally.false_detections;
      tally.hidden_on_true_row += t.label == StripeColumnLabel::hidden_from_camera && std::abs(error) <= options.row_tolerance_px;
      tally.off_surface += off_every_surface(d, model, pose, scene, options.off_surface_m);
      tally.no_laser_light += !on_laser_light(d, renderer, options);
    }
  }
  return sum_sq;
}

double tally_geometric(const StructuredLightFrameTruth& truth, const StructuredLightRailOptions& options,
                       StripeTally& tally) {
  double sum_sq = 0.0;
  std::size_t next = 0;
  for (const StripeColumnTruth& t : truth.columns) {
    if (t.label != StripeColumnLabel::visible) continue;
    ++tally.truth_visible;
    ++tally.detected;
    const double error = truth.stripe[next++].v_px - t.v_px;
    if (std::abs(error) <= options.row_tolerance_px) {
      ++tally.correct;
      sum_sq += error * error;
    } else {
      ++tally.false_detections;
    }
  }
  return sum_sq;
}

}  // namespace

std::vector<Eigen::Vector2d> stripe_floor_points(const StructuredLightParameters& parameters, const TrunkPose& pose,
                                                 double floor_elevation_m) {
  Scene floor;
  floor.terrain.base_elevation_m = floor_elevation_m;
  StructuredLightSimulator simulator(floor, parameters);
  StructuredLightFrameTruth frame;
  simulator.simulate(pose, frame);
  std::vector<Eigen::Vector2d> points(frame.columns.size(),
                                      Eigen::Vector2d::Constant(std::numeric_limits<double>::quiet_NaN()));
  for (std::size_t i = 0; i < frame.columns.size(); ++i) {
    if (frame.columns[i].label == StripeColumnLabel::visible) points[i] = frame.columns[i].point_m.head<2>();
  }
  return points;
}

namespace detail {

void run_structured_light_rail(const Scene& scene, const CartRailOptions& options,
                               const std::vector<TrunkPose>& poses, CartRailResult& result) {
  const StructuredLightRailOptions& sl = options.structured_light;
  if (!(sl.row_tolerance_px > 0.0) || !(sl.min_confidence >= 0.0 && sl.min_confidence <= 1.0) ||
      !(sl.off_surface_m > 0.0 && sl.off_surface_m < 1.0) || !(sl.laser_light_min_snr > 0.0)) {
    throw InputError(
        "cart rail: structured light: row_tolerance_px must be > 0, min_confidence in [0, 1], off_surface_m in "
        "(0, 1) m and laser_light_min_snr > 0");
  }
  const StructuredLightModel model(sl.parameters);
  ground_stripe_report(model);  // a clear error when this mount cannot see the ground
  const double floor_m = scene.terrain.base_elevation_m;
  const std::vector<Eigen::Vector2d> first = stripe_floor_points(sl.parameters, poses.front(), floor_m);
  const std::vector<Eigen::Vector2d> last = stripe_floor_points(sl.parameters, poses.back(), floor_m);
  Eigen::Vector2d lo = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector2d hi = -lo;
  for (const auto* points : {&first, &last}) {
    for (const Eigen::Vector2d& p : *points) {
      if (!p.allFinite()) continue;
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
  }
  if (!lo.allFinite()) throw InputError("cart rail: the structured-light stripe does not meet the floor in the image");
  PipelineOptions pipeline_options = rail_pipeline_options(lo, hi, options, sl.parameters.mount);
  pipeline_options.sensor = SensorKind::structured_light;
  pipeline_options.structured_light = sl.parameters;
  MappingPipeline pipeline(pipeline_options);
  centre_rail_map(lo, hi, pipeline);
  TopPointObserver top_points(pipeline);

  std::optional<StructuredLightImageRenderer> renderer;
  std::optional<StructuredLightSimulator> simulator;
  if (sl.pipeline == StripePipeline::image) {
    renderer.emplace(scene, sl.parameters, sl.image, sl.geometry, options.seed);
  } else {
    simulator.emplace(scene, sl.parameters, sl.geometry, options.seed);
  }
  io::StripeDetector detector(sl.detector);
  io::RgbImage image(sl.parameters.image_width_px, sl.parameters.image_height_px);
  io::StripeDetection detection;
  StructuredLightFrameTruth truth;
  std::vector<StripePixel> pixels;
  double sum_sq = 0.0;
  TopVisibility visibility = rail_top_visibility(scene, result.rail);
  for (const TrunkPose& pose : poses) {
    if (options.progress) options.progress(static_cast<std::size_t>(&pose - poses.data()), poses.size());
    if (renderer) {
      renderer->render(pose, image.rgb, &truth);
      detector.detect(image, detection);
      detection.pixels(pixels, sl.min_confidence);
      sum_sq += tally_frame(detection, truth, sl, model, pose, scene, *renderer, result.stripe);
    } else {
      simulator->simulate(pose, truth);
      pixels = truth.stripe;
      sum_sq += tally_geometric(truth, sl, result.stripe);
    }
    for (const StripeColumnTruth& column : truth.columns) {
      if (column.label == StripeColumnLabel::visible) visibility.add_hit(column.object_index, column.point_m);
    }
    ++result.stripe.frames;
    result.stripe.columns += truth.columns.size();
    pipeline.add(pixels, std::nullopt, pose);  // no time: the rail's frames come in order by construction
  }
  result.stripe_conversion = pipeline.stats().stripe;
  result.stripe.map_points = result.stripe_conversion.converted;
  result.stripe.row_error_rms_px =
      result.stripe.correct ? std::sqrt(sum_sq / static_cast<double>(result.stripe.correct)) : 0.0;
  result.scans = poses.size();
  finish_rail_map(scene, options, pipeline, [&](const ElevationMap& map) { return swept_area_between(map, first, last); },
                  visibility, result);
}

}  // namespace detail
}  // namespace stridemap
