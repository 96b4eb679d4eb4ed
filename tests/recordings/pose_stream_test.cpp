// Pose files and named pipes: what a line may hold, what is refused (with
// file and line), and reading a pipe while another process writes it.
#include <gtest/gtest.h>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cstdio>
#include <string>
#include <string_view>
#include <vector>

#include "live/test_folder.hpp"
#include "stridemap/core/error.hpp"
#include "stridemap/recordings/pose_stream.hpp"

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

// The first message about a skipped line of a file that has one good pose
// (at time 100) after the line under test.
std::string skipped_of(test::TestFolder& dir, const std::string& name, const std::string& text) {
  PoseLineProblems problems;
  const auto poses = read_pose_file(dir.write(name, text + "100 0 0 0 0 0\n"), &problems);
  EXPECT_EQ(poses.size(), 1u) << name;
  EXPECT_EQ(problems.count, 1u) << name;
  return problems.first.empty() ? "nothing skipped" : problems.first.front();
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

// One bad record never costs the others: each bad line is skipped, counted
// and named with file and line, and the poses around it are kept.
TEST(PoseStream, BadLinesAreSkippedAndNamedWithFileAndLine) {
  test::TestFolder dir;
  EXPECT_EQ(skipped_of(dir, "a.txt", "1 2 3\n"),
            dir / "a.txt" + ":1: 3 fields; expected at least 6: time_s x_m y_m yaw_rad pitch_rad roll_rad "
                            "[reference_elevation_m [height_change_m [z_m]]]");
  EXPECT_EQ(skipped_of(dir, "b.txt", "# c\n1 2 3 4 5 six\n"), dir / "b.txt" + ":2: field 6 'six' is not a finite number");
  EXPECT_EQ(skipped_of(dir, "c.txt", "1 0 0 0 0 nan\n"), dir / "c.txt" + ":1: field 6 'nan' is not a finite number");
  EXPECT_NE(skipped_of(dir, "d.txt", "1 0 0 0 0 0 0 0 0.3 10\n").find(":1: more than 9 fields"), std::string::npos);
  EXPECT_EQ(skipped_of(dir, "z.txt", "1 0 0 0 0 0 0 0 inf\n"), dir / "z.txt" + ":1: field 9 'inf' is not a finite number");
  EXPECT_EQ(error_of(dir.write("e.txt", "# nothing\n")), dir / "e.txt" +
                ": no usable pose in the file (expected lines of time_s x_m y_m yaw_rad pitch_rad roll_rad "
                "[reference_elevation_m [height_change_m [z_m]]])");
  EXPECT_EQ(error_of(dir.write("f.txt", "garbage\n")), dir / "f.txt" +
                ": no usable pose in the file (expected lines of time_s x_m y_m yaw_rad pitch_rad roll_rad "
                "[reference_elevation_m [height_change_m [z_m]]]); the first bad line: " + dir / "f.txt" +
                ":1: field 1 'garbage' is not a finite number");
  EXPECT_NE(error_of(dir / "missing.txt").find("cannot open the pose file"), std::string::npos);
  // Many bad lines: all counted, the first 20 named, every good pose kept.
  std::string text;
  for (int i = 0; i < 50; ++i) text += std::to_string(i) + " 0 0 0 0 " + (i % 2 ? "x" : "0") + "\n";
  PoseLineProblems problems;
  EXPECT_EQ(read_pose_file(dir.write("g.txt", text), &problems).size(), 25u);
  EXPECT_EQ(problems.count, 25u);
  EXPECT_EQ(problems.first.size(), PoseLineProblems::kListed);
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
  // A line that drops (or adds) z within a file is skipped and named.
  PoseLineProblems problems;
  EXPECT_EQ(read_pose_file(dir.write("m.txt", "1 0 0 0 0 0 0 0 0.4\n2 0 0 0 0 0\n"), &problems).size(), 1u);
  ASSERT_EQ(problems.count, 1u);
  EXPECT_NE(problems.first.front().find("m.txt:2: pose at 2 s has no z but the previous pose has one"),
            std::string::npos) << problems.first.front();
}

TEST(PoseStream, OutOfOrderTimesAreSkippedWithTheLine) {
  test::TestFolder dir;
  PoseLineProblems problems;
  const auto poses = read_pose_file(dir.write("o.txt", "1.0 0 0 0 0 0\n1.1 0 0 0 0 0\n1.05 0 0 0 0 0\n1.2 0 0 0 0 0\n"),
                                    &problems);
  ASSERT_EQ(poses.size(), 3u);
  EXPECT_EQ(poses[2].time_s, 1.2);
  ASSERT_EQ(problems.count, 1u);
  EXPECT_NE(problems.first[0].find("o.txt:3: pose time 1.05 s is not later than the previous pose's 1.1 s"),
            std::string::npos)
      << problems.first[0];
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
  const std::string backwards = "1.15 0 0 0 0 0\nnan 0 0 0 0 0\n1.3 0 0 0 0 0\n";
  ASSERT_EQ(::write(writer, backwards.data(), backwards.size()), static_cast<ssize_t>(backwards.size()));
  EXPECT_EQ(reader.poll(track), 1u);  // the two bad lines skipped, the good one after them kept
  EXPECT_EQ(track.last_time_s(), 1.3);
  EXPECT_EQ(reader.skipped_lines(), 2u);
  const std::vector<std::string> notices = reader.take_notices();
  ASSERT_EQ(notices.size(), 2u);
  EXPECT_NE(notices[0].find("poses.fifo:4: pose time 1.15 s is not later"), std::string::npos) << notices[0];
  EXPECT_NE(notices[1].find("poses.fifo:5: field 1 'nan'"), std::string::npos) << notices[1];
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
TEST(PoseStream, OverlongLineIsSkippedAlikeInAFileAndAStreamInAnyPieces) {
  const std::string text = "0.1 0 0 0 0 0\n0.2 0 0 0 0 0" + std::string(5000, ' ') + "\n0.3 0 0 0 0 0\n";
  const std::string expected = "p.txt:2: line longer than 4096 bytes: not a pose line";
  PoseLineProblems whole;
  EXPECT_EQ(parse_pose_text(text, "p.txt", &whole).size(), 2u);
  ASSERT_EQ(whole.first.size(), 1u);
  EXPECT_EQ(whole.first[0], expected);
  for (const std::size_t piece : {1u, 7u, 4096u, 5000u, 6000u}) {
    PoseLineBuffer lines("p.txt");
    std::size_t poses = 0;
    for (std::size_t pos = 0; pos < text.size(); pos += piece) {
      lines.feed(std::string_view(text).substr(pos, piece), [&](const TimedPose&) { ++poses; });
      EXPECT_LE(lines.pending_bytes(), kMaxPoseLineBytes);
    }
    EXPECT_EQ(poses, 2u) << "pieces of " << piece;
    ASSERT_EQ(lines.problems().first.size(), 1u) << "pieces of " << piece;
    EXPECT_EQ(lines.problems().first[0], expected) << "pieces of " << piece;
    EXPECT_EQ(lines.lines(), 3u) << "pieces of " << piece;
  }
}

// A restarted pose publisher: it writes a new file over the old one, or
// truncates the old one and starts again. Both are seen, reported, and the
// new poses read; the ones known already are not read twice.
TEST(PoseStream, FileReplacedOrTruncatedUnderTheReaderIsReopened) {
  test::TestFolder dir;
  const std::string path = dir.write("poses.txt", "1.0 0 0 0 0 0\n2.0 0 0 0 0 0\n");
  PoseStreamReader reader(path);
  PoseTrack track(100.0);
  EXPECT_EQ(reader.poll(track), 2u);
  // Replaced: a new file renamed over the path (another inode).
  const std::string fresh = dir.write("poses.new", "1.0 0 0 0 0 0\n2.0 0 0 0 0 0\n3.0 0 0 0 0 0\n");
  ASSERT_EQ(std::rename(fresh.c_str(), path.c_str()), 0);
  EXPECT_EQ(reader.poll(track), 1u);
  EXPECT_EQ(track.last_time_s(), 3.0);
  EXPECT_EQ(reader.reopened(), 1u);
  std::vector<std::string> notices = reader.take_notices();
  ASSERT_EQ(notices.size(), 1u);
  EXPECT_NE(notices[0].find("poses.txt: replaced by a new file"), std::string::npos) << notices[0];
  EXPECT_EQ(reader.skipped_lines(), 0u);  // known poses are no bad lines
  // Truncated in place and written anew.
  {
    std::FILE* f = std::fopen(path.c_str(), "w");
    ASSERT_NE(f, nullptr);
    std::fputs("4.0 0 0 0 0 0\n", f);
    std::fclose(f);
  }
  EXPECT_EQ(reader.poll(track), 1u);
  EXPECT_EQ(track.last_time_s(), 4.0);
  EXPECT_EQ(reader.reopened(), 2u);
  notices = reader.take_notices();
  ASSERT_EQ(notices.size(), 1u);
  EXPECT_NE(notices[0].find("poses.txt: cut to 14 bytes after 42 were read"), std::string::npos) << notices[0];
  // Growing as usual afterwards.
  {
    std::FILE* f = std::fopen(path.c_str(), "a");
    std::fputs("5.0 0 0 0 0 0\n", f);
    std::fclose(f);
  }
  EXPECT_EQ(reader.poll(track), 1u);
  EXPECT_EQ(reader.reopened(), 2u);
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
