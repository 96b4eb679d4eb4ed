// A pose file read in step with a replay (io::PoseFileCursor): the same
// poses and skipped lines as reading it whole, with the track holding only
// the poses just ahead of the time asked for.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "live/test_folder.hpp"
#include "stridemap/core/error.hpp"
#include "stridemap/recordings/pose_stream.hpp"

namespace stridemap::io {
namespace {

// Poses 0.01 s apart but for a hole of 0.1 s, with a bad line, a pose out
// of order and a last line without its LF among them.
std::string pose_text(int count) {
  std::string text = "# time_s x_m y_m yaw_rad pitch_rad roll_rad\n";
  for (int k = 0; k < count; ++k) {
    if (k >= 3000 && k < 3010) continue;  // a hole of 0.1 s
    TimedPose pose;
    pose.time_s = 100.0 + 0.01 * k;
    pose.pose.x_m = 0.003 * k;
    text += format_pose_line(pose) + "\n";
    if (k == 10) text += "not a pose\n";
    if (k == 20) text += "50 0 0 0 0 0\n";  // before the poses around it
  }
  text.pop_back();
  return text;
}

TEST(PoseFileCursor, GivesTheWholeFilesPosesAndSkippedLinesInStep) {
  test::TestFolder dir;
  const std::string path = dir.write("poses.txt", pose_text(20000));
  PoseLineProblems whole_problems;
  const std::vector<TimedPose> whole = read_pose_file(path, &whole_problems);

  PoseFileCursor cursor(path);
  PoseTrack track(1.0);
  std::size_t most_held = 0;
  for (double t = 99.0; t < 310.0; t += 0.05) {
    cursor.read_to(t, track);
    most_held = std::max(most_held, track.size());
    if (!cursor.ended()) EXPECT_GE(track.last_time_s(), t);
    track.drop_before(t);  // as the pipeline does after each scan
  }
  EXPECT_TRUE(cursor.ended());
  EXPECT_EQ(cursor.poses(), whole.size());
  EXPECT_EQ(cursor.first_time_s(), whole.front().time_s);
  EXPECT_EQ(cursor.last_time_s(), whole.back().time_s);
  EXPECT_EQ(cursor.problems().count, whole_problems.count);
  EXPECT_EQ(cursor.problems().first, whole_problems.first);
  // A block of the file at a time, not the file.
  EXPECT_LT(most_held, whole.size() / 4) << "the track held " << most_held << " of " << whole.size() << " poses";
}

// What a replay asks of the track, at scan times between and beyond the
// poses: the same answer, bit for bit, as from the whole file.
TEST(PoseFileCursor, InterpolatesAsTheWholeFileDoes) {
  test::TestFolder dir;
  const std::string path = dir.write("poses.txt", pose_text(5000));
  PoseTrack whole(0.015);  // the hole is a gap too wide
  for (const TimedPose& pose : read_pose_file(path)) whole.append(pose);
  PoseFileCursor cursor(path);
  PoseTrack streamed(0.015);
  for (double t = 99.99; t < 150.3; t += 0.0137) {
    cursor.read_to(t, streamed);
    TrunkPose a, b;
    const PoseLookup from_whole = whole.interpolate(t, a);
    ASSERT_EQ(streamed.interpolate(t, b), from_whole) << t;
    if (from_whole == PoseLookup::ok) {
      EXPECT_EQ(a.x_m, b.x_m) << t;
      EXPECT_EQ(a.yaw_rad, b.yaw_rad) << t;
    }
    whole.drop_before(t);
    streamed.drop_before(t);
  }
}

TEST(PoseFileCursor, AFileWithoutAUsablePoseIsRefusedAtOnce) {
  test::TestFolder dir;
  const std::string path = dir.write("poses.txt", "# nothing\nnot a pose\n");
  try {
    PoseFileCursor cursor(path);
    ADD_FAILURE() << "a file without a pose was taken";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("no usable pose in the file"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("poses.txt:2"), std::string::npos) << e.what();
  }
  EXPECT_THROW(PoseFileCursor(dir.path()), InputError);  // a folder
}

}  // namespace
}  // namespace stridemap::io
