#include "stridemap/sensors/scip_encoding.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

#include "stridemap/core/error.hpp"

namespace stridemap::scip {
namespace {

TEST(ScipEncoding, SpecExamplesDecode) {
  EXPECT_EQ(decode_value("CB"), 1234u);         // spec Fig. 2/3
  EXPECT_EQ(decode_value("1Dh"), 5432u);        // spec Fig. 4/5
  EXPECT_EQ(decode_value("m2@0"), 16000000u);   // spec Fig. 6/7
}

TEST(ScipEncoding, RealDeviceValuesDecode) {
  EXPECT_EQ(decode_value("ZR3h"), 11149560u);  // timestamp of the real UG01 GD reply
  EXPECT_EQ(decode_value("11N"), 4190u);
  EXPECT_EQ(decode_value("0fa"), 3505u);
  EXPECT_EQ(decode_value("0dG"), 3351u);
  EXPECT_EQ(decode_value("006"), 6u);
  EXPECT_EQ(decode_value("0C"), 19u);   // SCIP 1.1 "non-measurable step"
  EXPECT_EQ(decode_value("QS"), 2147u);
}

TEST(ScipEncoding, ChecksumsOfSpecAndDeviceLines) {
  EXPECT_EQ(checksum("Hokuyo"), 'o');
  EXPECT_EQ(checksum("00"), 'P');
  EXPECT_EQ(checksum("99"), 'b');
  EXPECT_EQ(checksum("02"), 'R');
  EXPECT_EQ(checksum("0E"), 'e');
  EXPECT_EQ(checksum("ZR3h"), '7');
  EXPECT_EQ(checksum("DMIN:20"), '4');
  EXPECT_EQ(checksum("VEND:Hokuyo Automatic Co.,Ltd."), '[');
  EXPECT_EQ(checksum("PROD:SOKUIKI Sensor URG-04LX-UG01(Simple-URG)"), '[');
  EXPECT_EQ(checksum("FIRM:3.4.03(17/Dec./2012)"), 'T');
  EXPECT_EQ(checksum("PROT:SCIP 2.0"), 'N');
  EXPECT_EQ(checksum("SERI:H1510998"), 'V');
  EXPECT_EQ(checksum("ARES:1024"), '\\');
  EXPECT_EQ(checksum(""), '0');
}

TEST(ScipEncoding, EncodeRoundTripsAtTheLimits) {
  for (int width = 2; width <= 4; ++width) {
    const std::uint32_t largest = max_encodable_value(width);
    for (const std::uint32_t value : {std::uint32_t{0}, std::uint32_t{1}, std::uint32_t{19}, largest / 3, largest}) {
      const std::string text = encode_value(value, width);
      ASSERT_EQ(text.size(), static_cast<std::size_t>(width));
      for (const char c : text) EXPECT_TRUE(is_data_char(c));
      EXPECT_EQ(decode_value(text), value);
    }
  }
  EXPECT_EQ(max_encodable_value(2), 4095u);
  EXPECT_EQ(max_encodable_value(3), 262143u);
  EXPECT_EQ(max_encodable_value(4), 16777215u);
  EXPECT_EQ(encode_value(1234, 2), "CB");
  EXPECT_EQ(encode_value(5432, 3), "1Dh");
  EXPECT_EQ(encode_value(16000000, 4), "m2@0");
}

TEST(ScipEncoding, CharacterValidityIsExactly0x30To0x6f) {
  int valid = 0;
  for (int byte = 0; byte < 256; ++byte) {
    const bool expected = byte >= 0x30 && byte <= 0x6F;
    EXPECT_EQ(is_data_char(static_cast<char>(byte)), expected) << byte;
    valid += expected ? 1 : 0;
  }
  EXPECT_EQ(valid, 64);
}

TEST(ScipEncoding, InvalidInputIsRejectedWithThePlace) {
  std::uint32_t value = 77;
  EXPECT_FALSE(try_decode_value("0p", value));
  EXPECT_FALSE(try_decode_value("/0", value));
  EXPECT_FALSE(try_decode_value("", value));
  EXPECT_FALSE(try_decode_value("00000", value));
  EXPECT_EQ(value, 77u);
  try {
    decode_value("0\x7f" "0");
    FAIL() << "no exception";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("character 1 is 0x7f"), std::string::npos) << error.what();
  }
  try {
    encode_value(4096, 2);
    FAIL() << "no exception";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("4096 does not fit in 2 characters (max 4095)"), std::string::npos)
        << error.what();
  }
  EXPECT_THROW(encode_value(1, 5), InputError);
}

TEST(ScipEncoding, DecodeValuesChecksLengthAndCharacters) {
  std::vector<std::uint32_t> values;
  decode_values("0060061Dh", 3, values);
  EXPECT_EQ(values, (std::vector<std::uint32_t>{6, 6, 5432}));
  decode_values("CB0C", 2, values);
  EXPECT_EQ(values, (std::vector<std::uint32_t>{1234, 19}));
  try {
    decode_values("00600", 3, values);
    FAIL() << "no exception";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("5 characters is not a multiple of 3"), std::string::npos);
  }
  try {
    decode_values("006 06", 3, values);
    FAIL() << "no exception";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("offset 3 is 0x20"), std::string::npos) << error.what();
  }
}

}  // namespace
}  // namespace stridemap::scip
