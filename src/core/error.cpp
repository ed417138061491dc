#include "isoforge/core/error.hpp"

#include <string>

namespace isoforge {

std::string at_line(std::string_view file, std::int64_t line, std::string_view what) {
  std::string s(file);
  if (line > 0) {
    s += ':';
    s += std::to_string(line);
  }
  s += ": ";
  s += what;
  return s;
}

std::string at_byte(std::string_view file, std::uint64_t offset, std::string_view what) {
  std::string s(file);
  s += ": byte ";
  s += std::to_string(offset);
  s += ": ";
  s += what;
  return s;
}

void invariant_failed(std::string_view what, const char* file, unsigned line) {
  throw Error(std::string(file) + ":" + std::to_string(line) +
              ": internal error: " + std::string(what) + " does not hold");
}

}  // namespace isoforge
