// Pose files and named pipes: what a line may hold, what is refused (with
// file and line), and reading a pipe while another process writes it.
#include <gtest/gtest.h>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <string>
#include <string_view>
#include <vector>

#include "live/test_folder.hpp"
#include "stridemap/core/error.hpp"
#include "stridemap/io/pose_stream.hpp"

namespace stridemap::io {
namespace {

std::string error_of(const std::string& path) {
  try {
    read_pose_file(path);
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

TEST(PoseStream, FileWithCommentsOptionalColumnsAndExactNumbers) {
  test::TestFolder dir;
  const std::string path = dir.write("poses.txt",
                                     "# time x y yaw pitch roll\n"
                                     "\n"
                                     "1733065200.1 0.25 0 0.5 0.01 -0.02\n"
                                     "1733065200.2\t0.26 0 0.5 0.01 -0.02 0.003 -0.004\r\n");
  const auto poses = read_pose_file(path);
  ASSERT_EQ(poses.size(), 2u);
  EXPECT_EQ(poses[0].time_s, 1733065200.1);
  EXPECT_EQ(poses[0].pose.yaw_rad, 0.5);
  EXPECT_EQ(poses[1].pose.reference_elevation_m, 0.003);
  EXPECT_EQ(poses[1].pose.height_change_m, -0.004);
  // Writing and reading back gives the same numbers bit for bit.
  TimedPose back;
  ASSERT_TRUE(parse_pose_line(format_pose_line(poses[1]), "x", 1, back));
  EXPECT_EQ(back.time_s, poses[1].time_s);
  EXPECT_EQ(back.pose.height_change_m, poses[1].pose.height_change_m);
}

TEST(PoseStream, BadLinesAreNamedWithFileAndLine) {
  test::TestFolder dir;
  EXPECT_EQ(error_of(dir.write("a.txt", "1 2 3\n")),
            dir / "a.txt" + ":1: 3 fields; expected at least 6: time_s x_m y_m yaw_rad pitch_rad roll_rad "
                            "[reference_elevation_m [height_change_m [z_m]]]");
  EXPECT_EQ(error_of(dir.write("b.txt", "# c\n1 2 3 4 5 six\n")), dir / "b.txt" + ":2: field 6 'six' is not a finite number");
  EXPECT_EQ(error_of(dir.write("c.txt", "1 0 0 0 0 nan\n")), dir / "c.txt" + ":1: field 6 'nan' is not a finite number");
  EXPECT_NE(error_of(dir.write("d.txt", "1 0 0 0 0 0 0 0 0.3 10\n")).find(":1: more than 9 fields"), std::string::npos);
  EXPECT_EQ(error_of(dir.write("z.txt", "1 0 0 0 0 0 0 0 inf\n")), dir / "z.txt" + ":1: field 9 'inf' is not a finite number");
  EXPECT_EQ(error_of(dir.write("e.txt", "# nothing\n")), dir / "e.txt" +
                ": no pose in the file (expected lines of time_s x_m y_m yaw_rad pitch_rad roll_rad "
                "[reference_elevation_m [height_change_m [z_m]]])");
  EXPECT_NE(error_of(dir / "missing.txt").find("cannot open the pose file"), std::string::npos);
}

TEST(PoseStream, NinthColumnIsTheTrunkHeightAndOlderFilesReadAsBefore) {
  test::TestFolder dir;
  const auto poses = read_pose_file(dir.write("z.txt",
                                              "1.0 0.25 0 0.5 0.01 -0.02\n"
                                              "2.0 0.25 0 0.5 0.01 -0.02 0.003 -0.004\n"));
  ASSERT_EQ(poses.size(), 2u);
  EXPECT_FALSE(poses[0].pose.z_m.has_value());
  EXPECT_FALSE(poses[1].pose.z_m.has_value());
  TimedPose p;
  ASSERT_TRUE(parse_pose_line("3.0 0.25 0 0.5 0.01 -0.02 0 0 0.4125", "x", 1, p));
  ASSERT_TRUE(p.pose.z_m.has_value());
  EXPECT_EQ(*p.pose.z_m, 0.4125);
  EXPECT_EQ(p.pose.reference_elevation_m, 0.0);
  // Written and read back: the ninth column only when there is a z, the
  // two paper columns kept as placeholders before it.
  EXPECT_EQ(format_pose_line(p), "3 0.25 0 0.5 0.01 -0.02 0 0 0.4125");
  TimedPose back;
  ASSERT_TRUE(parse_pose_line(format_pose_line(p), "x", 1, back));
  EXPECT_EQ(back.pose.z_m, p.pose.z_m);
  EXPECT_EQ(format_pose_line(poses[0]), "1 0.25 0 0.5 0.01 -0.02");
  EXPECT_EQ(format_pose_line(poses[1]), "2 0.25 0 0.5 0.01 -0.02 0.003 -0.004");
  // A file that gives z on some lines only is refused at the first change.
  const std::string mixed = error_of(dir.write("m.txt", "1 0 0 0 0 0 0 0 0.4\n2 0 0 0 0 0\n"));
  EXPECT_NE(mixed.find("m.txt:2: pose at 2 s has no z but the previous pose has one"), std::string::npos) << mixed;
}

TEST(PoseStream, OutOfOrderTimesAreRefusedWithTheLine) {
  test::TestFolder dir;
  const std::string message = error_of(dir.write("o.txt", "1.0 0 0 0 0 0\n1.1 0 0 0 0 0\n1.05 0 0 0 0 0\n"));
  EXPECT_NE(message.find("o.txt:3: pose time 1.05 s is not later than the previous pose's 1.1 s"), std::string::npos)
      << message;
}

TEST(PoseStream, NamedPipeIsReadAsItIsWrittenWithoutBlocking) {
  test::TestFolder dir;
  const std::string fifo = dir / "poses.fifo";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  PoseStreamReader reader(fifo);  // must not wait for a writer
  EXPECT_TRUE(reader.is_pipe());
  PoseTrack track;
  EXPECT_EQ(reader.poll(track), 0u);
  const int writer = ::open(fifo.c_str(), O_WRONLY | O_NONBLOCK);
  ASSERT_GE(writer, 0);
  const std::string first = "1.0 0 0 0 0 0\n1.1 0.01 0 0 0 0\n1.2 0.0";
  ASSERT_EQ(::write(writer, first.data(), first.size()), static_cast<ssize_t>(first.size()));
  EXPECT_EQ(reader.poll(track), 2u);  // the half line waits for its end
  const std::string rest = "2 0 0 0 0\n";
  ASSERT_EQ(::write(writer, rest.data(), rest.size()), static_cast<ssize_t>(rest.size()));
  EXPECT_EQ(reader.poll(track), 1u);
  EXPECT_EQ(track.last_time_s(), 1.2);
  const std::string backwards = "1.15 0 0 0 0 0\n";
  ASSERT_EQ(::write(writer, backwards.data(), backwards.size()), static_cast<ssize_t>(backwards.size()));
  try {
    reader.poll(track);
    ADD_FAILURE() << "out-of-order pose accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("poses.fifo:4: pose time 1.15 s is not later"), std::string::npos) << e.what();
  }
  ::close(writer);
  EXPECT_EQ(reader.poll(track), 0u);  // the writer went away: no error, nothing new
}

TEST(PoseStream, SourceThatIsNeitherFileNorPipeIsRefused) {
  test::TestFolder dir;
  EXPECT_THROW(PoseStreamReader(dir.path().string()), InputError);
  EXPECT_THROW(PoseStreamReader(dir / "missing"), InputError);
}

// A line that never ends must not fill the memory of a live stream, and the
// same bytes must be read alike from a file and through a pipe in any pieces.
TEST(PoseStream, OverlongLineIsRefusedAlikeInAFileAndAStreamInAnyPieces) {
  const std::string text = "0.1 0 0 0 0 0\n0.2 0 0 0 0 0" + std::string(5000, ' ') + "\n0.3 0 0 0 0 0\n";
  const std::string expected = "p.txt:2: line longer than 4096 bytes: not a pose line";
  try {
    parse_pose_text(text, "p.txt");
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), expected);
  }
  for (const std::size_t piece : {1u, 7u, 4096u, 5000u, 6000u}) {
    PoseLineBuffer lines("p.txt");
    std::size_t poses = 0;
    try {
      for (std::size_t pos = 0; pos < text.size(); pos += piece) {
        lines.feed(std::string_view(text).substr(pos, piece), [&](const TimedPose&) { ++poses; });
        EXPECT_LE(lines.pending_bytes(), kMaxPoseLineBytes);
      }
      ADD_FAILURE() << "no error in pieces of " << piece;
    } catch (const InputError& e) {
      EXPECT_EQ(std::string(e.what()), expected) << "pieces of " << piece;
    }
    EXPECT_EQ(poses, 1u);
  }
}

TEST(PoseStream, StreamKeepsAnUnfinishedLastLineUntilItsEnd) {
  PoseLineBuffer lines("pipe");
  std::vector<TimedPose> got;
  const auto use = [&](const TimedPose& p) { got.push_back(p); };
  lines.feed("0.1 0 0 0 0 0\n0.2 1 0 0", use);
  EXPECT_EQ(got.size(), 1u);
  lines.feed(" 0 0\r\n", use);
  ASSERT_EQ(got.size(), 2u);
  EXPECT_EQ(got[1].pose.x_m, 1.0);
  EXPECT_EQ(lines.lines(), 2u);
}

}  // namespace
}  // namespace stridemap::io
