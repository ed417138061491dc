#include "progress_bar.hpp"

#include <unistd.h>

#include <algorithm>
#include <cstdio>

namespace isoforge::cli {

bool stderr_is_tty() { return ::isatty(STDERR_FILENO) != 0; }

ProgressBar::ProgressBar(bool enabled) : enabled_(enabled) {}

ProgressBar::~ProgressBar() { finish(); }

void ProgressBar::stage(std::string name) {
  stage_ = std::move(name);
  last_ = {};
  update(0.0);
}

void ProgressBar::update(double fraction) {
  if (!enabled_) return;
  const auto now = std::chrono::steady_clock::now();
  if (fraction < 1.0 && now - last_ < std::chrono::milliseconds(50)) return;
  last_ = now;
  draw(std::clamp(fraction, 0.0, 1.0));
}

void ProgressBar::draw(double fraction) {
  constexpr int kWidth = 30;  // characters of bar
  const int filled = static_cast<int>(fraction * kWidth + 0.5);
  std::string bar(static_cast<std::size_t>(filled), '#');
  bar.resize(kWidth, '.');
  std::fprintf(stderr, "\r%-12s [%s] %3d%%", stage_.c_str(), bar.c_str(),
               static_cast<int>(fraction * 100 + 0.5));
  std::fflush(stderr);
  drawn_ = true;
}

void ProgressBar::finish() {
  if (enabled_ && drawn_) {
    std::fprintf(stderr, "\r%60s\r", "");
    std::fflush(stderr);
    drawn_ = false;
  }
}

ProgressCallback ProgressBar::callback() {
  if (!enabled_) return {};
  return [this](double f) {
    update(f);
    return true;
  };
}

}  // namespace isoforge::cli
