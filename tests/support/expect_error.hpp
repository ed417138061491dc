#pragma once
// expect_error(f, text): f() must throw isoforge::Error whose message contains `text`;
// error_message(f): the message of the Error f() throws, for tests that check several parts.

#include <gtest/gtest.h>

#include <string>

#include "isoforge/core/error.hpp"

namespace isoforge::test {

template <class F>
void expect_error(F&& f, const std::string& text) {
  try {
    f();
    ADD_FAILURE() << "no Error thrown, expected one containing '" << text << "'";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(text), std::string::npos)
        << "message: " << e.what() << "\nexpected to contain: " << text;
  }
}

/// The message of the `Error` that f() throws, or "<no error>".
template <class F>
std::string error_message(F&& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "<no error>";
}

}  // namespace isoforge::test
