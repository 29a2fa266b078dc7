#include <gtest/gtest.h>

#include <cmath>

#include "shore/core/hash.h"

// Reference values of 64-bit FNV-1a from its specification (offset basis 0xcbf29ce484222325).
TEST(StateHash, MatchesPublishedFnv1aVectors) {
  shore::StateHash empty;
  EXPECT_EQ(empty.value(), 0xcbf29ce484222325ull);
  shore::StateHash a;
  a.add_bytes("a", 1);
  EXPECT_EQ(a.value(), 0xaf63dc4c8601ec8cull);
  shore::StateHash foobar;
  foobar.add_bytes("foobar", 6);
  EXPECT_EQ(foobar.value(), 0x85944171f73967e8ull);
}

TEST(StateHash, DistinguishesOneBitAndFormatsAsHex) {
  shore::StateHash h1, h2;
  h1.add(1.0);
  h2.add(std::nextafter(1.0, 2.0));
  EXPECT_NE(h1.value(), h2.value());
  EXPECT_EQ(shore::to_hex(0xaf63dc4c8601ec8cull), "af63dc4c8601ec8c");
}
