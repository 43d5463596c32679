// The names users type: every kind and every Embree mode round-trips
// through its one spelling, the bench's Embree rows too, and a wrong name
// is refused; SplitMix64 is the published generator.
#include <gtest/gtest.h>

#include "mbrt/build_options.h"
#include "mbrt/splitmix.h"

using namespace mbrt;

TEST(Names, KindsRoundTrip) {
  for (AccelKind k : availableAccelKinds()) EXPECT_EQ(parseAccelKind(toString(k)), k) << toString(k);
  EXPECT_FALSE(parseAccelKind("bvh"));
  EXPECT_FALSE(parseAccelKind(""));
}

TEST(Names, EmbreeModesHaveOneSpelling) {
  using M = BuildOptions::EmbreeMode;
  for (M m : {M::Robust, M::Default, M::Static, M::StaticRobust}) {
    EXPECT_EQ(parseEmbreeMode(toString(m)), m) << toString(m);
    EXPECT_EQ(parseEmbreeRow(embreeRowName(m)), m) << embreeRowName(m);
  }
  EXPECT_EQ(embreeRowName(M::Default), "embree");  // Embree as its users run it
  EXPECT_EQ(embreeRowName(M::Robust), "embree-robust");
  EXPECT_EQ(embreeRowName(M::StaticRobust), "embree-static-robust");
  EXPECT_EQ(toString(M::StaticRobust), "static-robust");
  for (const char* bad : {"embree-default", "embree-", "embree-fast", "robust", "stbvh"})
    EXPECT_FALSE(parseEmbreeRow(bad)) << bad;
  EXPECT_FALSE(parseEmbreeMode("embree"));
}

TEST(Names, SplitMixIsTheReferenceGenerator) {
  // The first outputs of SplitMix64 seeded with 0 (Steele et al. 2014's
  // reference implementation).
  uint64_t state = 0;
  EXPECT_EQ(splitmix64(state), 0xE220A8397B1DCDAFull);
  EXPECT_EQ(splitmix64(state), 0x6E789E6AA1B965F4ull);
  EXPECT_EQ(toUnitFloat(~0ull), 16777215.0f / 16777216.0f);
}
