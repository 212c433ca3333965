// Base64 against RFC 4648's test vectors (src/io/base64.cpp).
#include "tricot/io/base64.hpp"

#include <gtest/gtest.h>

#include <string>

namespace tricot::io {
namespace {

TEST(Base64, MatchesTheTestVectorsOfRfc4648) {
  EXPECT_EQ(base64(""), "");
  EXPECT_EQ(base64("f"), "Zg==");
  EXPECT_EQ(base64("fo"), "Zm8=");
  EXPECT_EQ(base64("foo"), "Zm9v");
  EXPECT_EQ(base64("foob"), "Zm9vYg==");
  EXPECT_EQ(base64("fooba"), "Zm9vYmE=");
  EXPECT_EQ(base64("foobar"), "Zm9vYmFy");
  EXPECT_EQ(base64(std::string("\xff\xfe\x00", 3)), "//4A");  // high bytes and NUL
}

}  // namespace
}  // namespace tricot::io
