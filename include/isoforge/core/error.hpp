#pragma once
/// \file
/// The one exception type isoforge throws for bad input, and the check of internal invariants.

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

/// Throws `Error` naming the place of a broken internal invariant (a bug in isoforge, never bad
/// input): "<file>:<line>: internal error: <what> does not hold".
[[noreturn]] void invariant_failed(std::string_view what, const char* file, unsigned line);

/// Checks an internal invariant; on failure throws `Error` naming `what` and the place — never
/// aborts, because the library must not take down its host program on a bug. The place defaults
/// to the caller's (the builtins behind `std::source_location`, which clang 14 lacks).
inline void check_invariant(bool holds, std::string_view what, const char* file = __builtin_FILE(),
                            unsigned line = __builtin_LINE()) {
  if (!holds) [[unlikely]]
    invariant_failed(what, file, line);
}

}  // namespace isoforge
