// Malformed frames: each is reported with the right reason, and the good
// frames on both sides of it still decode.
#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "stridemap/sensors/scip_decoder.hpp"
#include "stridemap/sensors/scip_encoding.hpp"
#include "stridemap/sensors/scip_reply_encoder.hpp"

namespace stridemap::scip {
namespace {

std::vector<std::uint32_t> scan_values(std::uint32_t seed, std::size_t count = 682) {
  std::vector<std::uint32_t> values(count);
  for (std::size_t i = 0; i < count; ++i) values[i] = (seed * 104729u + static_cast<std::uint32_t>(i) * 53u) % 5600u;
  return values;
}

std::string md_frame(std::uint32_t seed, std::string_view echo = "MD0044072501000") {
  std::string bytes;
  append_distance_reply(parse_command(echo), 1000 + seed, scan_values(seed), bytes);
  return bytes;
}

std::vector<std::string> split_lines(const std::string& frame) {
  std::vector<std::string> lines;
  std::size_t start = 0;
  for (std::size_t lf = frame.find('\n'); lf != std::string::npos; lf = frame.find('\n', start)) {
    lines.push_back(frame.substr(start, lf - start));
    start = lf + 1;
  }
  return lines;
}

std::string join_lines(const std::vector<std::string>& lines) {
  std::string out;
  for (const auto& line : lines) out += line + '\n';
  return out;
}

// Frame A, the bad bytes, frame B: expects exactly A, one error, B.
void expect_reported_between_good_frames(const std::string& bad, ErrorKind kind, std::string_view message_part) {
  const std::string a = md_frame(1);
  const std::string b = md_frame(2);
  const auto events = decode_all(a + bad + b);
  ASSERT_EQ(events.size(), 3u) << "bad bytes: " << bad.substr(0, 80);
  ASSERT_EQ(events[0].kind, EventKind::distance);
  EXPECT_EQ(events[0].distance.values, scan_values(1));
  ASSERT_EQ(events[1].kind, EventKind::error);
  EXPECT_EQ(events[1].error.kind, kind) << events[1].error.message;
  EXPECT_NE(events[1].error.message.find(message_part), std::string::npos) << events[1].error.message;
  EXPECT_EQ(events[1].stream_offset, a.size());
  ASSERT_EQ(events[2].kind, EventKind::distance) << events[2].error.message;
  EXPECT_EQ(events[2].distance.values, scan_values(2));
  EXPECT_EQ(events[2].stream_offset, a.size() + bad.size());
}

std::string corrupt_line(std::size_t line_number, std::size_t column, char replacement) {
  auto lines = split_lines(md_frame(7));
  lines[line_number - 1][column - 1] = replacement;
  return join_lines(lines);
}

TEST(ScipCorruption, BadChecksumOnADataLine) {
  auto lines = split_lines(md_frame(7));
  char& c = lines[5][20];  // line 6 = third data line
  c = static_cast<char>(c == '0' ? '1' : c - 1);
  expect_reported_between_good_frames(join_lines(lines), ErrorKind::bad_checksum, "bad checksum on line 6 of reply 'MD0044072501000' (status 99) (data)");
}

TEST(ScipCorruption, InvalidCharacterNamesColumnAndOffset) {
  const std::string bad = corrupt_line(5, 10, '\x7f');
  const std::size_t expected_offset = md_frame(1).size() + bad.find('\x7f');
  expect_reported_between_good_frames(bad, ErrorKind::invalid_character,
                                      "invalid character 0x7f at column 10 of line 5 of reply 'MD0044072501000' (status 99) (data) at stream offset " +
                                          std::to_string(expected_offset));
}

TEST(ScipCorruption, WrongDataLengthExpectedVersusGot) {
  std::string fewer;
  append_distance_frame("MD0044072501000", "99", 5, scan_values(3, 681), 3, fewer);
  expect_reported_between_good_frames(fewer, ErrorKind::wrong_data_length,
                                      "expected 682 values (2046 characters) from the echo, got 2043 characters");
  std::string more;
  append_distance_frame("MD0044072501000", "99", 5, scan_values(3, 690), 3, more);
  expect_reported_between_good_frames(more, ErrorKind::wrong_data_length,
                                      "the echo announces 2046 data characters, but line 35");
}

TEST(ScipCorruption, EchoAndStatusProblems) {
  expect_reported_between_good_frames("XY0001\n00P\n\n", ErrorKind::unknown_echo,
                                      "reply to an unknown command: echo 'XY0001'");
  expect_reported_between_good_frames("GD0044072501\n0L" + std::string(1, checksum("0L")) + "\n\n",
                                      ErrorKind::unknown_status, "unknown status '0L' for command GD on line 2");
  expect_reported_between_good_frames("BM\n00Q\n\n", ErrorKind::bad_checksum,
                                      "bad checksum on line 2 of reply 'BM'");
  expect_reported_between_good_frames("BM\n0P\n\n", ErrorKind::bad_status_line, "has 2 characters, expected 3");
  expect_reported_between_good_frames("BM\n\n", ErrorKind::bad_status_line, "without a status line");
  expect_reported_between_good_frames("BM\n00P\n0060\n\n", ErrorKind::unexpected_payload,
                                      "reply 'BM' (status 00) carries no data");
  auto lines = split_lines(md_frame(4, "GD0044072501"));
  lines[0] = "GD00x4072501";
  lines[1] = "00P";
  expect_reported_between_good_frames(join_lines(lines), ErrorKind::bad_echo_parameters,
                                      "start step '00x4' is not 4 decimal digits");
  lines[0] = "GD0725004401";
  expect_reported_between_good_frames(join_lines(lines), ErrorKind::bad_echo_parameters,
                                      "end step is before start step");
}

TEST(ScipCorruption, TimestampAndLineLengthProblems) {
  expect_reported_between_good_frames("GD0044072501\n00P\n\n", ErrorKind::missing_payload, "without its timestamp line");
  auto lines = split_lines(md_frame(5));
  lines[2] = "ZR37";
  expect_reported_between_good_frames(join_lines(lines), ErrorKind::bad_line_length,
                                      "timestamp line 3 of reply 'MD0044072501000' (status 99)");
  lines = split_lines(md_frame(5));
  lines[4].erase(10, 1);  // a valid but short line in the middle of the data
  lines[4].back() = checksum(std::string_view(lines[4]).substr(0, lines[4].size() - 1));
  expect_reported_between_good_frames(join_lines(lines), ErrorKind::bad_line_length,
                                      "has 63 data characters but is not the last line");
  lines = split_lines(md_frame(5));
  lines[6] += "000000";
  expect_reported_between_good_frames(join_lines(lines), ErrorKind::bad_line_length, "has 71 characters, expected 2..65");
  // A lost LF merges two data lines.
  lines = split_lines(md_frame(5));
  lines[5] += 'A' + lines[6];
  lines.erase(lines.begin() + 6);
  expect_reported_between_good_frames(join_lines(lines), ErrorKind::bad_line_length, "has 131 characters");
}

TEST(ScipCorruption, FramesCutShortByTheNextEcho) {
  // Ten lines of a frame, then nothing: the next echo ends it.
  auto lines = split_lines(md_frame(6));
  lines.resize(10);
  expect_reported_between_good_frames(join_lines(lines), ErrorKind::unexpected_echo,
                                      "holds the echo 'MD0044072501000' of a new reply");
  // A whole frame without its blank line.
  std::string no_blank = md_frame(6);
  no_blank.pop_back();
  expect_reported_between_good_frames(no_blank, ErrorKind::unexpected_echo, "ended without its blank line");
  // A status-only reply without its blank line.
  expect_reported_between_good_frames("BM\n00P\n", ErrorKind::unexpected_echo, "line 3 of reply 'BM' (status 00)");
}

TEST(ScipCorruption, EchoThatPassesAsADataLineIsRecovered) {
  // Pick a tag that makes the echo line's last character its own checksum,
  // so it is taken for a short last data line; the status that follows
  // reveals it.
  std::string echo;
  for (char tag = 'a'; tag <= 'o' && echo.empty(); ++tag) {
    const std::string candidate = "MD0044072501000;" + std::string(1, tag) + "0";
    for (char last = '0'; last <= 'o'; ++last) {
      std::string line = candidate + last;
      if (checksum(std::string_view(line).substr(0, line.size() - 1)) == last && parse_command(line).well_formed) {
        echo = line;
        break;
      }
    }
  }
  ASSERT_FALSE(echo.empty());
  auto lines = split_lines(md_frame(8));
  lines.resize(12);
  const std::string a = md_frame(1);
  const std::string cut = join_lines(lines);
  const std::string b = md_frame(2, echo);
  const auto events = decode_all(a + cut + b);
  ASSERT_EQ(events.size(), 3u);
  EXPECT_EQ(events[1].error.kind, ErrorKind::unexpected_echo) << events[1].error.message;
  EXPECT_EQ(events[1].byte_count, cut.size());
  ASSERT_EQ(events[2].kind, EventKind::distance) << events[2].error.message;
  EXPECT_EQ(events[2].reply.echo.text, echo);
  EXPECT_EQ(events[2].distance.values, scan_values(2));
}

TEST(ScipCorruption, GarbageBeforeAFrame) {
  expect_reported_between_good_frames("hello world\nmore garbage\n\n", ErrorKind::garbage,
                                      "garbage before a frame: line 'hello world'");
  // Glued to the echo: the garbage is cut off and the frame decodes.
  const std::string a = md_frame(1);
  const std::string b = md_frame(2);
  const auto events = decode_all(a + "\x01\xff" "zz" + b);
  ASSERT_EQ(events.size(), 3u);
  EXPECT_EQ(events[1].error.kind, ErrorKind::garbage);
  EXPECT_NE(events[1].error.message.find("4 bytes of garbage '\\x01\\xffzz' before the echo"), std::string::npos)
      << events[1].error.message;
  EXPECT_EQ(events[1].byte_count, 4u);
  ASSERT_EQ(events[2].kind, EventKind::distance);
  EXPECT_EQ(events[2].stream_offset, a.size() + 4);
  // The blank line of A lost: A is reported, B (glued to A's last byte) decodes.
  std::string a_damaged = a;
  a_damaged.back() = 'x';
  const auto cut = decode_all(a_damaged + b);
  ASSERT_EQ(cut.size(), 2u);
  EXPECT_EQ(cut[0].error.kind, ErrorKind::unexpected_echo) << cut[0].error.message;
  ASSERT_EQ(cut[1].kind, EventKind::distance);
  EXPECT_EQ(cut[1].distance.values, scan_values(2));
}

TEST(ScipCorruption, ErrorCarriesEchoStatusAndLine) {
  const auto events = decode_all(corrupt_line(9, 3, '\x01'));
  ASSERT_EQ(events.size(), 1u);
  const DecodeError& error = events[0].error;
  EXPECT_EQ(error.kind, ErrorKind::invalid_character);
  EXPECT_EQ(error.echo, "MD0044072501000");
  EXPECT_EQ(error.status, "99");
  EXPECT_EQ(error.line, 9u);
  EXPECT_EQ(events[0].byte_count, md_frame(7).size());
}

TEST(ScipCorruption, LineWithoutEndIsCutAndMemoryStaysBounded) {
  Decoder decoder;
  Event event;
  std::vector<Event> events;
  const std::string chunk(65536, 'A');
  for (int i = 0; i < 160; ++i) {  // 10 MiB without LF
    decoder.feed(chunk);
    while (decoder.next(event)) events.push_back(event);
    ASSERT_EQ(decoder.pending_bytes(), 0u);
  }
  decoder.feed("\n\n" + md_frame(3));
  while (decoder.next(event)) events.push_back(event);
  ASSERT_GE(events.size(), 3u);
  EXPECT_EQ(events.front().error.kind, ErrorKind::line_too_long);
  EXPECT_NE(events.front().error.message.find("no LF within 256 bytes"), std::string::npos);
  std::size_t dropped = 0;
  for (std::size_t i = 0; i + 1 < events.size(); ++i) {
    ASSERT_EQ(events[i].kind, EventKind::error);
    EXPECT_LE(events[i].byte_count, 2 * decoder.options().max_frame_bytes);
    dropped += events[i].byte_count;
  }
  EXPECT_EQ(dropped, 160u * 65536u + 2u);
  EXPECT_EQ(events[1].error.kind, ErrorKind::frame_too_long);
  ASSERT_EQ(events.back().kind, EventKind::distance);
  EXPECT_EQ(events.back().distance.values, scan_values(3));
}

TEST(ScipCorruption, FrameWithoutEndIsCut) {
  std::string endless = "MD0044072501000\n99b\nZR3h7\n";
  const std::string data_line = std::string(64, '0') + checksum(std::string(64, '0')) + "\n";
  for (int i = 0; i < 2000; ++i) endless += data_line;
  const auto events = decode_all(endless + "\n" + md_frame(4));
  ASSERT_GE(events.size(), 2u);
  EXPECT_EQ(events[0].error.kind, ErrorKind::wrong_data_length) << events[0].error.message;
  ASSERT_EQ(events.back().kind, EventKind::distance);
  // With a data length that never overflows (a huge echo), the frame limit cuts it.
  std::string huge_frame = "MD0000999901000\n99b\nZR3h7\n";
  for (int i = 0; i < 400; ++i) huge_frame += data_line;
  const auto huge = decode_all(huge_frame + "\n" + md_frame(4));
  ASSERT_GE(huge.size(), 2u);
  EXPECT_EQ(huge[0].error.kind, ErrorKind::frame_too_long) << huge[0].error.message;
  EXPECT_NE(huge[0].error.message.find("without its blank line (limit 16384)"), std::string::npos);
  ASSERT_EQ(huge.back().kind, EventKind::distance);
}

// Random single and multiple byte corruptions in a stream of frames: no
// crash, every frame whose bytes are intact decodes exactly, and no frame
// decodes to values other than those sent.
TEST(ScipCorruption, RandomCorruptionLosesOnlyTheDamagedFrames) {
  constexpr std::size_t kFrames = 6;
  std::string clean;
  std::vector<std::size_t> starts;
  for (std::uint32_t i = 0; i < kFrames; ++i) {
    starts.push_back(clean.size());
    clean += md_frame(i);
  }
  starts.push_back(clean.size());
  std::mt19937_64 rng(7);
  std::uniform_int_distribution<std::size_t> position(0, clean.size() - 1);
  std::uniform_int_distribution<int> byte(0, 255);
  std::uniform_int_distribution<int> hits(1, 3);
  for (int trial = 0; trial < 400; ++trial) {
    std::string bytes = clean;
    std::vector<bool> damaged(kFrames, false);
    for (int h = hits(rng); h > 0; --h) {
      const std::size_t at = position(rng);
      char replacement = static_cast<char>(byte(rng));
      if (replacement == bytes[at]) replacement = static_cast<char>(replacement ^ 0x01);
      bytes[at] = replacement;
      for (std::size_t f = 0; f < kFrames; ++f) {
        if (at >= starts[f] && at < starts[f + 1]) damaged[f] = true;
      }
    }
    std::vector<bool> decoded(kFrames, false);
    for (const auto& event : decode_all(bytes)) {
      if (event.kind != EventKind::distance) continue;
      std::size_t frame = kFrames;
      for (std::size_t f = 0; f < kFrames; ++f) {
        if (event.stream_offset == starts[f]) frame = f;
      }
      ASSERT_LT(frame, kFrames) << "trial " << trial << ": a frame decoded at an unexpected offset";
      EXPECT_EQ(event.distance.values, scan_values(static_cast<std::uint32_t>(frame))) << "trial " << trial;
      decoded[frame] = true;
    }
    for (std::size_t f = 0; f < kFrames; ++f) {
      EXPECT_TRUE(damaged[f] || decoded[f]) << "trial " << trial << ": intact frame " << f << " lost";
    }
  }
}

TEST(ScipCorruption, ArbitraryBytesNeverCrash) {
  std::mt19937_64 rng(11);
  std::uniform_int_distribution<int> byte(0, 255);
  std::uniform_int_distribution<int> length(0, 4000);
  const std::string alphabet = "\n\n\n0123456789:;ABDEGMPQRSTVbo";
  std::uniform_int_distribution<std::size_t> pick(0, alphabet.size() - 1);
  std::size_t events = 0;
  for (int trial = 0; trial < 300; ++trial) {
    std::string bytes;
    const int n = length(rng);
    for (int i = 0; i < n; ++i) {
      bytes += trial % 2 == 0 ? static_cast<char>(byte(rng)) : alphabet[pick(rng)];
    }
    events += decode_all(bytes).size();
  }
  EXPECT_GT(events, 0u);
}

}  // namespace
}  // namespace stridemap::scip
