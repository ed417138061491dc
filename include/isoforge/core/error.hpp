#pragma once
/// \file
/// The one exception type isoforge throws for bad input, and the internal assertion macro.

#include <cstdint>
#include <stdexcept>
#include <string>
#include <string_view>

namespace isoforge {

/// Thrown for bad input: a malformed or truncated file, an invalid argument, an out-of-range
/// index. The message always names the file or argument and says what is wrong, e.g.
/// `"mesh.vtk:12: POINTS count -3 is negative"` or `"contour: isovalue is NaN"`.
class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& message) : std::runtime_error(message) {}
};

/// Builds the message "<file>:<line>: <what>" (line is 1-based; 0 omits it).
[[nodiscard]] std::string at_line(std::string_view file, std::int64_t line, std::string_view what);

/// Builds the message "<file>: byte <offset>: <what>".
[[nodiscard]] std::string at_byte(std::string_view file, std::uint64_t offset,
                                  std::string_view what);

namespace detail {
[[noreturn]] void assertion_failed(const char* expr, const char* file, int line);
}  // namespace detail

}  // namespace isoforge

/// Internal invariant check that names file and line. Throws `isoforge::Error` (never aborts),
/// because the library must not take down its host program on a bug.
#define ISOFORGE_ASSERT(expr) \
  ((expr) ? static_cast<void>(0) : ::isoforge::detail::assertion_failed(#expr, __FILE__, __LINE__))
