#include "stridemap/pipeline/structured_light_sensor.hpp"

namespace stridemap {

StructuredLightSensor::StructuredLightSensor(const StructuredLightParameters& parameters) : model_(parameters) {}

}  // namespace stridemap
