#include "stridemap/core/printable_text.hpp"

#include <string>

#include <gtest/gtest.h>

namespace stridemap {
namespace {

TEST(PrintableText, TextWithoutControlBytesIsUnchanged) {
  const std::string plain = "bad.yaml:7: boxes[0].length_m: expected a positive number, got -0.2\nsecond line";
  EXPECT_EQ(printable_text(plain), plain);
  EXPECT_EQ(printable_text("Überhöhung 5 °, 高さ, 🙂"), "Überhöhung 5 °, 高さ, 🙂");
}

TEST(PrintableText, EveryByteATerminalWouldObeyIsEscaped) {
  EXPECT_EQ(printable_text("got \x1b[2J\x1b]0;owned\x07!"), "got \\x1b[2J\\x1b]0;owned\\x07!");
  EXPECT_EQ(printable_text(std::string("a\0b\rc\td\x7f", 8)), "a\\x00b\\x0dc\\x09d\\x7f");
  // C1 controls: CSI raw (0x9b) and in its UTF-8 form (C2 9B).
  EXPECT_EQ(printable_text("x\x9b" "2Jy"), "x\\x9b2Jy");
  EXPECT_EQ(printable_text("x\xc2\x9b" "2Jy"), "x\\xc2\\x9b2Jy");
  // Not UTF-8: a lone lead byte, an overlong form, a surrogate, a cut sequence.
  EXPECT_EQ(printable_text("\xc3"), "\\xc3");
  EXPECT_EQ(printable_text("\xc0\xaf"), "\\xc0\\xaf");
  EXPECT_EQ(printable_text("\xed\xa0\x80"), "\\xed\\xa0\\x80");
  EXPECT_EQ(printable_text("\xe2\x82"), "\\xe2\\x82");
}

TEST(PrintableText, EscapedTextHasNoByteBelowSpaceButNewline) {
  std::string all;
  for (int b = 0; b < 256; ++b) all += static_cast<char>(b);
  for (const char c : printable_text(all)) {
    const auto byte = static_cast<unsigned char>(c);
    EXPECT_TRUE(byte == '\n' || (byte >= 0x20 && byte != 0x7f && byte < 0x80)) << static_cast<int>(byte);
  }
}

}  // namespace
}  // namespace stridemap
