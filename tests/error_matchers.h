#pragma once
// Checks on the nsf::Error a call must throw: that it throws, and what its message names.
#include <gtest/gtest.h>

#include <string>

#include "core/error.h"

namespace nsf::testing {

// Runs f and returns the message of the nsf::Error it must throw.
template <typename Fn>
std::string error_of(Fn&& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  ADD_FAILURE() << "no nsf::Error was thrown";
  return "";
}

inline void expect_contains(const std::string& msg, const std::string& part) {
  EXPECT_NE(msg.find(part), std::string::npos) << "'" << part << "' missing from: " << msg;
}

}  // namespace nsf::testing
