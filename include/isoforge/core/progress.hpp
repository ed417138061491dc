#pragma once
/// \file
/// Progress reporting and cancellation for long operations (house rule 8).

#include <functional>

#include "isoforge/core/error.hpp"

namespace isoforge {

/// Called by long operations with the completed fraction in [0, 1]. Return `false` to cancel:
/// the operation then stops at the next check and throws `Cancelled`. An empty function is
/// never called. Calls come from the calling thread only.
using ProgressCallback = std::function<bool(double fraction)>;

/// Thrown when a `ProgressCallback` asked to cancel.
class Cancelled : public Error {
 public:
  explicit Cancelled(const std::string& what) : Error(what + ": cancelled") {}
};

/// Reports `fraction` to `callback` (if set); throws `Cancelled` naming `operation` if the
/// callback returns false.
inline void report_progress(const ProgressCallback& callback, double fraction,
                            const char* operation) {
  if (callback && !callback(fraction)) throw Cancelled(operation);
}

/// A callback that maps its fraction f to from + f (to − from) of `parent`, for a stage of a
/// longer operation; empty when `parent` is.
[[nodiscard]] inline ProgressCallback progress_range(const ProgressCallback& parent, double from,
                                                     double to) {
  if (!parent) return {};
  return [parent, from, to](double f) { return parent(from + f * (to - from)); };
}

}  // namespace isoforge
