// `stridemap map --bag`: the node's map, offline, from a ROS 1 bag through
// the same MessageMapper (docs/ros.md).
#include "map_bag.hpp"

#include <cstdio>

#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "output_guard.hpp"
#include "terminal_output.hpp"
#include "stridemap/core/error.hpp"
#include "stridemap/core/printable_text.hpp"
#include "stridemap/io/text_file.hpp"
#include "stridemap/mapfile/map_outputs.hpp"
#include "stridemap_ros/bag_mapping.hpp"
#include "stridemap_ros/map_saving.hpp"
#include "stridemap_ros/message_mapper_library.hpp"

namespace stridemap::cli {
namespace {

// What the run did, for scripts: every count the summary line gives and
// the map's coverage, under the names of MessageMapperStats.
nlohmann::json bag_summary_json(const MapBagArgs& args, const ros_adapter::MessageMapper& mapper, double coverage) {
  const ros_adapter::MessageMapperStats& s = mapper.stats();
  return {{"command", "map --bag"},
          {"bag", args.bag_path},
          {"scan_topic", args.scan_topic},
          {"cloud_topic", args.cloud_topic},
          {"scans",
           {{"offered", s.scans},
            {"mapped", s.mapped},
            {"before_first_pose", s.before_first_pose},
            {"dropped",
             {{"wrong_frame", s.wrong_frame},
              {"stamp_not_increasing", s.stamp_not_increasing},
              {"bad_fields", s.bad_geometry},
              {"unreadable", s.unreadable},
              {"no_valid_beams", s.no_valid_beams},
              {"pose_timeout", s.pose_timeout},
              {"pose_unavailable", s.pose_unavailable},
              {"queue_full", s.queue_full},
              {"refused_by_mapper", s.rejected_by_mapper}}},
            {"last_drop", mapper.last_drop()},
            {"last_bad_fields", mapper.last_bad_scan()}}},
          {"beams",
           {{"offered", s.beams},
            {"not_finite", s.beams_not_finite},
            {"out_of_range", s.beams_out_of_range},
            {"low_intensity", s.beams_low_intensity}}},
          {"map", {{"coverage", coverage}}}};
}

}  // namespace

void run_map_bag(const MapBagArgs& args, const std::string& config_path, const std::string& out_dir) {
  if (args.scan_topic.empty() == args.cloud_topic.empty()) {
    throw InputError("--bag: give one of --scan-topic or --cloud-topic");
  }
  if (args.tf == !args.pose_topic.empty()) throw InputError("--bag: give one of --pose-topic or --tf");
  ros_adapter::BagMappingOptions options;
  options.bag_path = args.bag_path;
  options.scan_topic = args.scan_topic;
  options.cloud_topic = args.cloud_topic;
  options.pose_topic = args.pose_topic;
  options.mapper.map_frame = args.map_frame;
  options.mapper.sensor_frame = args.sensor_frame;
  options.mapper.pose_wait_s = args.pose_wait_s;
  options.mapper.max_pose_gap_s = args.max_pose_gap_s;
  options.mapper.range_error_m = args.range_error_m;
  options.mapper.range_error_fraction = args.range_error_fraction;
  options.mapper.min_intensity = args.min_intensity;
  options.mapper.config_path = config_path;
  refuse_output_that_is_an_input("--out", out_dir, {{"--bag", args.bag_path}, {"--config", config_path}});
  io::check_output_folder(out_dir, "--out", other_files(args.overwrite));
  ros_adapter::BagMapping mapping(options);
  {
    io::ProgressBar bar = progress_bar("map", "messages");
    mapping.run([&bar](std::size_t done, std::size_t total) { bar.update(done, total); });
  }
  const ros_adapter::MessageMapper& mapper = mapping.mapper();
  const ros_adapter::MessageMapperStats& s = mapper.stats();
  const ExportedMap layers = export_map(mapper.impl().pipeline->filtered_map());
  write_output_set(out_dir, "--out", [&](const std::string& dir) {
    io::MapOutputOptions outputs;
    outputs.certainty_max = mapper.impl().config.mapper.update.certainty_max;
    io::write_map_layers(layers, dir, outputs);
    std::set<std::string> written;
    ros_adapter::save_map(mapper, dir + "/map.smap", "map --bag " + args.bag_path, written);
    io::write_text_file(dir + "/summary.json", bag_summary_json(args, mapper, map_coverage(layers)).dump(2) + "\n",
                        "run summary");
  }, other_files(args.overwrite));
  std::printf("map: %zu scans mapped of %zu, %zu before the first pose (dropped: %zu wrong frame, %zu stamp not increasing, %zu unreadable, "
              "%zu bad scan fields, %zu no valid beams, %zu pose timeout, %zu pose unavailable, %zu queue full, "
              "%zu refused by the mapper), %zu NaN ranges; coverage %.1f %%; outputs: %s\n",
              s.mapped, s.scans, s.before_first_pose, s.wrong_frame, s.stamp_not_increasing, s.unreadable, s.bad_geometry,
              s.no_valid_beams, s.pose_timeout, s.pose_unavailable, s.queue_full, s.rejected_by_mapper, s.beams_not_finite,
              100.0 * map_coverage(layers), printable_text(out_dir).c_str());
  if (s.bad_geometry > 0) {
    std::fprintf(stderr, "stridemap: warning: %zu scans with bad fields dropped; the last: %s\n", s.bad_geometry,
                 printable_text(mapper.last_bad_scan()).c_str());
  }
  std::fflush(stdout);
  if (s.mapped == 0) throw RunFailed(args.bag_path + ": no scan was mapped (" + mapper.last_drop() + ")");
}

}  // namespace stridemap::cli
