#pragma once
/// \file
/// The one convention for what algorithms return (docs/architecture.md, "API conventions"):
/// an algorithm returns its output by value; one that also reports statistics returns a
/// `Result` holding both, e.g. `auto [surface, stats] = contour(volume, options);`.

namespace isoforge {

/// An algorithm's output and the statistics of the run that made it.
template <class Output, class Stats>
struct Result {
  Output output;  ///< what the algorithm produced (a dataset, a grid, ...)
  Stats stats;    ///< counts and measurements of the run
};

}  // namespace isoforge
