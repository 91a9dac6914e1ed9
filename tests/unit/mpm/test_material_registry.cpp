#include <gtest/gtest.h>

#include "core/error.h"
#include "mpm/materials/material.h"

TEST(Registry, KnowsFixedCorotated) {
  EXPECT_NO_THROW(nsf::make_material("fixed_corotated"));
}
TEST(Registry, RejectsUnknownType) {
  EXPECT_THROW(nsf::make_material("nope"), nsf::Error);
}
