// CRC-32 without zlib (src/core/crc32.h): the model file's checksum, checked by the runtime too.
#include <gtest/gtest.h>

#include <random>
#include <string>

#include "core/crc32.h"

// The check value of the CRC-32 used by zip and zlib, and an empty input.
TEST(Crc32, GivesTheStandardCheckValue) {
  EXPECT_EQ(nsf::crc32_of("123456789", 9), 0xCBF43926u);
  EXPECT_EQ(nsf::crc32_of("", 0), 0u);
  EXPECT_EQ(nsf::crc32_of("a", 1), 0xE8B7BE43u);
}

// Eight bytes at a time or one: the same value, and a CRC continued over a split input is the
// CRC of the whole.
TEST(Crc32, ContinuesOverPiecesOfAnyLength) {
  std::mt19937 rng(1);
  std::string s(1000, '\0');
  for (char& c : s) c = char(rng());
  const uint32_t whole = nsf::crc32_of(s.data(), s.size());
  for (size_t cut : {0u, 1u, 7u, 8u, 9u, 500u, 999u}) {
    const uint32_t head = nsf::crc32_of(s.data(), cut);
    EXPECT_EQ(nsf::crc32_of(s.data() + cut, s.size() - cut, head), whole) << cut;
  }
  uint32_t bytewise = 0;
  for (char c : s) bytewise = nsf::crc32_of(&c, 1, bytewise);
  EXPECT_EQ(bytewise, whole);
}
