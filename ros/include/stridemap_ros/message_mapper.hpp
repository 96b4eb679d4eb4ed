#pragma once
// The ROS adapter's one decision maker, free of ROS: scans as plain data
// (what a sensor_msgs/LaserScan or PointCloud2 carries), a pose source, and
// the library's MappingPipeline behind it. The ROS 1 node, `stridemap map
// --bag` and a future ROS 2 node all feed this class, so the same messages
// in the same order give the same map bit for bit (docs/ros.md).
//
// Every scan is either mapped or dropped with a reason; nothing in a
// message can crash it. A scan waits (bounded) for its pose: TF that has
// not reached the scan's stamp yet, or a pose topic that has not.
//
// This header is C++17 and names no library type beyond Eigen: ROS 1's
// message headers do not compile as C++20 (std::allocator<void>::rebind is
// gone), so the ROS side is built as C++17 and meets the C++20 library only
// through this header, map_saving.hpp and bag_mapping.hpp.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Geometry>

namespace stridemap::ros_adapter {

/// What a sensor_msgs/LaserScan carries, without ROS. Beam k points at
/// angle_min + k angle_increment in the scan's x-y plane (x ahead, y left).
/// The whole scan takes the pose at its stamp (the first beam's time, as
/// LaserScan's header says and the library's URG scans are stamped): the
/// paper's one pose per scan; time_increment is not used.
struct LaserScanData {
  double stamp_s = 0.0;
  std::string frame_id;
  double angle_min_rad = 0.0;
  double angle_increment_rad = 0.0;
  double range_min_m = 0.0;
  double range_max_m = 0.0;
  const float* ranges_m = nullptr;  ///< range_count values, valid during add()
  std::size_t range_count = 0;
  const float* intensities = nullptr;  ///< none, or one per range
  std::size_t intensity_count = 0;
};

/// Points of a sensor_msgs/PointCloud2 (the stripe camera's profile), in
/// the message's frame; sigma per point optional.
struct PointCloudData {
  double stamp_s = 0.0;
  std::string frame_id;
  std::vector<Eigen::Vector3d> points_m;
  std::vector<double> height_sigma_m;  ///< empty: MessageMapperOptions' range sigma model
};

struct MessageMapperOptions {
  /// Mount, map, update rule, fill-in: the same YAML file the CLI reads
  /// (docs/config.md); empty: the defaults.
  std::string config_path{};
  /// Frame of the map (TF's fixed frame, or the pose topic's frame).
  std::string map_frame = "map";
  /// Frame the scans must carry; empty: the first scan's frame, then that one.
  std::string sensor_frame{};
  /// Delta r of eq. (6), a beam's maximum range error: max(range_error_m,
  /// range_error_fraction x range), the URG-04LX's specified accuracy by
  /// default (10 mm, 1 % beyond 1 m), as the library's URG model uses it.
  /// A cloud point without a sigma field gets that bound / 3 as its height
  /// sigma (the bound read as 3 sigma, as the point sensor scales it back).
  double range_error_m = 0.01;
  double range_error_fraction = 0.01;
  /// Beams with an intensity below this are not used (0: all, and the
  /// intensities are not looked at; only when the message has intensities).
  double min_intensity = 0.0;
  /// A scan whose pose has not come this long after the scan (on the clock
  /// of `now_s` given to process()) is dropped as pose_timeout.
  double pose_wait_s = 0.5;
  /// Pose topic: no interpolation between poses farther apart than this.
  double max_pose_gap_s = 1.0;
  /// Scans kept waiting for a pose at most (older ones are dropped as queue_full).
  std::size_t max_waiting = 200;
  /// Keep the fused height layers fused_elevation and fused_variance
  /// (core/height_fusion.hpp): a walking robot's own height read where its
  /// feet stand (core/stance_height.hpp). The node keeps them when ~layers
  /// names either; the config's height_fusion.enabled keeps them too.
  bool fused_heights = false;

  /// Throws InputError naming the field.
  void validate() const;
};

/// Why scans were not mapped, and what was wrong with beams of mapped ones.
struct MessageMapperStats {
  std::size_t scans = 0;                 ///< offered
  std::size_t mapped = 0;                ///< reached the mapper and were integrated
  std::size_t wrong_frame = 0;           ///< frame_id not the sensor frame
  std::size_t stamp_not_increasing = 0;  ///< stamp not later than the previous scan's
  std::size_t bad_geometry = 0;          ///< angle increment, limits or sizes unusable
  std::size_t unreadable = 0;            ///< a cloud without float x, y, z fields, or sizes not matching its data
  std::size_t no_valid_beams = 0;
  std::size_t pose_timeout = 0;      ///< the pose (TF or topic) did not come within pose_wait_s
  std::size_t pose_unavailable = 0;  ///< the pose can never come (a gap, a transform not finite)
  /// Scans older than the pose source's first pose while no scan has been
  /// mapped yet: the usual start-up, where the sensor starts before TF or
  /// odometry. Counted apart from the drops, which mean something is wrong.
  std::size_t before_first_pose = 0;
  std::size_t queue_full = 0;
  std::size_t rejected_by_mapper = 0;  ///< pose or time refused by the mapper
  std::size_t beams = 0;
  std::size_t beams_not_finite = 0;     ///< NaN range (a point: a NaN or infinite coordinate)
  std::size_t beams_out_of_range = 0;   ///< outside [range_min, range_max], or +-Inf (REP-117)
  std::size_t beams_low_intensity = 0;
  std::size_t scans_with_bad_beams = 0;  ///< mapped or not: at least one NaN range
  std::size_t poses = 0;                 ///< pose messages offered (pose topic)
  std::size_t poses_rejected = 0;        ///< wrong frame, not finite, not later than the last
  double latency_sum_s = 0.0;            ///< arrival to mapped, summed over mapped scans
  double latency_max_s = 0.0;

  std::size_t dropped() const {
    return wrong_frame + stamp_not_increasing + bad_geometry + unreadable + no_valid_beams + pose_timeout +
           pose_unavailable + queue_full + rejected_by_mapper;
  }
};

/// Where a scan's pose comes from.
enum class PoseAnswer : std::uint8_t { ok, not_yet, never };

class PoseSource {
 public:
  virtual ~PoseSource() = default;
  /// The sensor frame `frame_id` in the map frame at `stamp_s`. `not_yet`:
  /// it may still come (TF has not reached the stamp). `why`, when given,
  /// says what is missing, for messages; words cost allocations, so the
  /// mapper asks for them only for a scan it drops.
  virtual PoseAnswer sensor_in_map(const std::string& frame_id, double stamp_s, Eigen::Isometry3d& out,
                                   std::string* why) = 0;
};

/// Poses from a PoseStamped / Odometry topic: the trunk's pose, interpolated
/// to the scan's stamp by the library's PoseTrack (MessageMapper asks it
/// directly, not through sensor_in_map).
class TopicPoseSource final : public PoseSource {
 public:
  explicit TopicPoseSource(double max_gap_s);
  ~TopicPoseSource() override;
  /// False (and nothing kept) for a pose not later than the last or not finite.
  bool add(double stamp_s, const Eigen::Isometry3d& trunk_in_map);
  PoseAnswer sensor_in_map(const std::string&, double, Eigen::Isometry3d&, std::string* why) override {
    if (why) *why = "a pose topic gives the trunk";
    return PoseAnswer::never;
  }
  /// Forgets poses no longer needed for scans at or after `stamp_s`.
  void drop_before(double stamp_s);

 private:
  friend class MessageMapper;
  struct Track;
  std::unique_ptr<Track> track_;
};

/// Map layers copied out for publishing: each layer's values as floats,
/// element (i, j) at values[i * cells_per_side + j] with i the cell's x
/// index from min_cell_x and j its y index (NaN: unknown elevation).
struct MapLayers {
  std::int64_t min_cell_x = 0;
  std::int64_t min_cell_y = 0;
  double cell_size_m = 0.0;
  int cells_per_side = 0;
  std::vector<std::string> names;
  std::vector<std::vector<float>> values;
};

class MessageMapper {
 public:
  /// Loads the config, checks the options; throws InputError naming the
  /// file, line and field, or the option. `poses` must outlive the mapper.
  MessageMapper(const MessageMapperOptions& options, PoseSource& poses);
  ~MessageMapper();

  /// Checks and converts a scan and queues it for its pose; `arrival_s` is
  /// when it came (the clock of process()'s `now_s`).
  void add(const LaserScanData& scan, double arrival_s);
  void add(const PointCloudData& cloud, double arrival_s);
  /// A message that could not be read as a scan (point_cloud_data said
  /// `why`): counted as offered and dropped, its stamp and frame unused.
  void add_unreadable(const std::string& frame_id, const std::string& why);
  /// Maps the waiting scans, oldest first, while their pose is there. A scan
  /// waiting longer than pose_wait_s (or any, with `end_of_stream`) whose
  /// pose is still missing is dropped. Returns the scans mapped.
  std::size_t process(double now_s, bool end_of_stream);
  /// An empty map, counts kept; the next scan may have any stamp.
  void clear();
  /// A pose message offered to the pose source, and whether it kept it (for the counts).
  void count_pose(bool kept) {
    ++stats_.poses;
    if (!kept) ++stats_.poses_rejected;
  }

  /// The named layers of the map with the config's fill-in applied to a
  /// copy. Throws InputError for an unknown name, listing the map's layers.
  MapLayers layers(const std::vector<std::string>& names) const;

  const MessageMapperStats& stats() const { return stats_; }
  std::size_t waiting() const;
  const MessageMapperOptions& options() const { return options_; }
  std::optional<double> last_mapped_stamp_s() const { return last_mapped_stamp_; }
  /// The last reason a scan was dropped, for diagnostics ("" if none).
  const std::string& last_drop() const { return last_drop_; }
  /// Why the last scan with bad fields (stats().bad_geometry) was dropped
  /// ("" if none): other drops later do not hide it.
  const std::string& last_bad_scan() const { return last_bad_scan_; }

  /// The library's side (message_mapper_library.hpp, C++20 only).
  struct Impl;
  const Impl& impl() const { return *impl_; }

 private:
  bool accept_header(double stamp_s, const std::string& frame_id);
  void drop(std::size_t& counter, const std::string& why);
  double range_error(double range_m) const;
  void make_room();
  /// A new pipeline from the config (and the fused layers' observer when
  /// asked for): at construction and at clear().
  void make_pipeline();

  MessageMapperOptions options_;
  PoseSource& poses_;
  std::unique_ptr<Impl> impl_;
  MessageMapperStats stats_;
  std::string sensor_frame_;
  std::optional<double> last_stamp_;
  std::optional<double> last_mapped_stamp_;
  std::string last_drop_;
  std::string last_bad_scan_;
};

}  // namespace stridemap::ros_adapter
