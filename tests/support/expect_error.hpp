#pragma once
// expect_error(f, text): f() must throw isoforge::Error whose message contains `text`.

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

}  // namespace isoforge::test
