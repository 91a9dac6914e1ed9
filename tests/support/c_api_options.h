#pragma once
// The C API's runtime options the C API tests run their tiny models with: μ = 1, two threads.
#include <gtest/gtest.h>
#include <nsf/nsf.h>

namespace nsf::testing {

inline nsf_runtime_options tiny_c_api_options() {
  nsf_runtime_options o;
  EXPECT_EQ(nsf_runtime_options_init(&o), NSF_OK);
  o.has_mu = 1;
  o.mu = 1.0;
  o.threads = 2;
  return o;
}

}  // namespace nsf::testing
