// plugin_symbol (core/plugin.hpp): the loader of isoforge's on-demand libraries.

#include "isoforge/core/plugin.hpp"

#include <gtest/gtest.h>

#include <string>

#include "isoforge/core/error.hpp"

namespace isoforge {
namespace {

std::string message_of(const char* name, const char* symbol) {
  try {
    (void)plugin_symbol(name, symbol, "plugin test");
  } catch (const Error& e) {
    return e.what();
  }
  return {};
}

TEST(Plugin, MissingLibraryIsAnErrorNamingIt) {
  const std::string m = message_of("libisoforge_no_such_part.so.0", "entry");
  EXPECT_NE(m.find("plugin test: cannot load libisoforge_no_such_part.so.0"), std::string::npos)
      << m;
}

TEST(Plugin, MissingSymbolIsAnErrorNamingIt) {
  // A library every process has loaded (the C library), asked for a symbol it lacks.
  const std::string m = message_of("libc.so.6", "isoforge_no_such_entry");
  EXPECT_NE(m.find("cannot load libc.so.6: it has no isoforge_no_such_entry"), std::string::npos)
      << m;
}

TEST(Plugin, FindsASymbol) {
  EXPECT_NE(plugin_symbol("libc.so.6", "strlen", "plugin test"), nullptr);
}

}  // namespace
}  // namespace isoforge
