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

namespace detail {
void assertion_failed(const char* expr, const char* file, int line) {
  throw Error(std::string("internal error: assertion '") + expr + "' failed at " + file + ":" +
              std::to_string(line));
}
}  // namespace detail

}  // namespace isoforge
