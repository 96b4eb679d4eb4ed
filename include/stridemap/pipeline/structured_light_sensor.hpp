#pragma once
// The camera + laser-stripe sensor as a pipeline sensor model: one frame's
// stripe pixels back-projected by eq. (1), placed by eq. (5), each with the
// error part of eq. (8) (sensors/structured_light_mapping.hpp).
#include <span>
#include <string_view>
#include <vector>

#include "stridemap/pipeline/sensor_model.hpp"
#include "stridemap/sensors/structured_light.hpp"
#include "stridemap/sensors/structured_light_mapping.hpp"

namespace stridemap {

/// One camera frame's detected stripe.
struct StripeFrame {
  double time_s = 0.0;
  std::vector<StripePixel> pixels;
};

class StructuredLightSensor final : public SensorModel {
 public:
  /// Throws InputError for invalid parameters (StructuredLightModel). The
  /// parameters' own mount is not used: the pipeline's mount places it.
  explicit StructuredLightSensor(const StructuredLightParameters& parameters);

  std::string_view name() const override { return "structured-light"; }
  /// The stripe the next to_points() converts; must stay valid until then.
  void set_frame(std::span<const StripePixel> pixels) { pixels_ = pixels; }
  void to_points(const TrunkPose& pose, const SensorMount& mount, const UpdateOptions& update,
                 PointBatch& batch) override {
    last_ = stripe_to_sensor_points(model_, pixels_, pose, mount, update, batch);
  }

  const StructuredLightModel& model() const { return model_; }
  /// Of the frame converted last.
  const StripeConversionStats& last_stats() const { return last_; }

 private:
  StructuredLightModel model_;
  std::span<const StripePixel> pixels_;
  StripeConversionStats last_;
};

}  // namespace stridemap
