#include "pipescope/util/base64.h"

#include <gtest/gtest.h>

namespace pipescope {
namespace {

// The test vectors of RFC 4648 §10.
TEST(Base64, Rfc4648TestVectors) {
  EXPECT_EQ(Base64Encode(""), "");
  EXPECT_EQ(Base64Encode("f"), "Zg==");
  EXPECT_EQ(Base64Encode("fo"), "Zm8=");
  EXPECT_EQ(Base64Encode("foo"), "Zm9v");
  EXPECT_EQ(Base64Encode("foob"), "Zm9vYg==");
  EXPECT_EQ(Base64Encode("fooba"), "Zm9vYmE=");
  EXPECT_EQ(Base64Encode("foobar"), "Zm9vYmFy");
}

TEST(Base64, HighBytesAndDataUrl) {
  EXPECT_EQ(Base64Encode(std::string("\xff\xfe\x00", 3)), "//4A");
  EXPECT_EQ(DataUrl("image/png", "foo"), "data:image/png;base64,Zm9v");
}

}  // namespace
}  // namespace pipescope
