#pragma once
// Checks on the nsf::Error a call must throw: that it throws, and what its message names.
#include <gtest/gtest.h>

#include <initializer_list>
#include <string>
#include <utility>

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

// Runs f expecting an nsf::Error whose message holds every one of `parts`.
template <typename Fn>
void expect_error(Fn&& f, std::initializer_list<std::string> parts) {
  const std::string msg = error_of(std::forward<Fn>(f));
  for (const std::string& part : parts) expect_contains(msg, part);
}

}  // namespace nsf::testing
