// SPDX-License-Identifier: AGPL-3.0-or-later
// Base64: RFC 4648's test vectors, a round trip of every byte value, and
// what decoding skips and refuses.
#include <gtest/gtest.h>

#include "palpa/core/base64.hpp"

namespace palpa {
namespace {

TEST(Base64, EncodesTheRfcVectors) {
  const std::pair<const char*, const char*> cases[] = {{"", ""},          {"f", "Zg=="},         {"fo", "Zm8="},
                                                       {"foo", "Zm9v"},   {"foob", "Zm9vYg=="}, {"fooba", "Zm9vYmE="},
                                                       {"foobar", "Zm9vYmFy"}};
  for (const auto& [plain, coded] : cases) {
    EXPECT_EQ(base64_encode(plain), coded) << plain;
    EXPECT_EQ(base64_decode(coded), std::string(plain)) << coded;
  }
}

TEST(Base64, RoundTripsEveryByte) {
  std::string bytes;
  for (int i = 0; i < 256; ++i) bytes.push_back(static_cast<char>(i));
  for (std::size_t n = 0; n < 4; ++n) {
    const std::string b = bytes.substr(0, bytes.size() - n);
    EXPECT_EQ(base64_decode(base64_encode(b)), b) << n;
  }
}

TEST(Base64, DecodingSkipsWhitespaceAndRefusesOtherCharacters) {
  EXPECT_EQ(base64_decode("Zm9v\nYmFy "), std::string("foobar"));
  EXPECT_FALSE(base64_decode("Zm9v*").has_value());
}

}  // namespace
}  // namespace palpa
