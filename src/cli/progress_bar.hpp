#pragma once
// Progress bar on stderr for the isoforge command (only when stderr is a terminal and --quiet
// is not given).

#include <chrono>
#include <string>

#include "isoforge/core/progress.hpp"

namespace isoforge::cli {

class ProgressBar {
 public:
  /// enabled = stderr is a TTY and not --quiet.
  explicit ProgressBar(bool enabled);
  ~ProgressBar();
  ProgressBar(const ProgressBar&) = delete;
  ProgressBar& operator=(const ProgressBar&) = delete;

  /// Starts a named stage ("reading", "contouring", ...) at 0%.
  void stage(std::string name);
  /// Updates the current stage; redraws at most ~20 times a second.
  void update(double fraction);
  /// Clears the bar line.
  void finish();
  /// A callback for library options that forwards to update().
  [[nodiscard]] ProgressCallback callback();
  [[nodiscard]] bool enabled() const { return enabled_; }

 private:
  void draw(double fraction);

  bool enabled_;
  bool drawn_ = false;
  std::string stage_;
  std::chrono::steady_clock::time_point last_{};
};

/// Whether stderr is attached to a terminal.
bool stderr_is_tty();

}  // namespace isoforge::cli
