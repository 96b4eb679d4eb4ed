#pragma once
// The library side of MessageMapper (C++20, no ROS): the pipeline and what
// converts ROS poses into the library's. For the adapter's own sources, the
// CLI's `map --bag` and tests; the ROS 1 sources never include it.
#include <memory>
#include <vector>

#include "stridemap/config/mapper_config.hpp"
#include "stridemap/core/planar_scan.hpp"
#include "stridemap/core/pose.hpp"
#include "stridemap/core/ring_queue.hpp"
#include "stridemap/pipeline/mapping_pipeline.hpp"
#include "stridemap_ros/message_mapper.hpp"

namespace stridemap::ros_adapter {

/// A rigid pose (REP-103 axes, as ROS gives them) as the library's trunk
/// pose: yaw, pitch (positive nose down), roll (positive left side up), z.
TrunkPose trunk_pose_from_isometry(const Eigen::Isometry3d& trunk_in_map);
/// The trunk pose that puts the sensor (placed on the trunk by `mount`) at
/// `sensor_in_map`.
TrunkPose trunk_pose_from_sensor(const Eigen::Isometry3d& sensor_in_map, const SensorMount& mount);

/// The pipeline the adapter runs: the generic point sensor, the config's
/// mount, map and update rule, the fill-in.
PipelineOptions message_pipeline_options(const MapperConfig& config);

struct MessageMapper::Impl {
  // A LaserScan is a planar scan (the library's eq. 6 model, the URG's);
  // a cloud is points with a sigma each (the generic point sensor).
  struct Waiting {
    bool planar = false;
    PlanarScan scan;
    PointFrame frame;
    double time_s = 0.0;
    std::string frame_id;
    double arrival_s = 0.0;
  };
  MapperConfig config;
  std::unique_ptr<MappingPipeline> pipeline;
  // Frames reused, so a steady stream does not allocate: a std::deque
  // freed and allocated a block every other scan.
  RingQueue<Waiting> waiting;
  std::vector<Waiting> spare;
};

}  // namespace stridemap::ros_adapter
