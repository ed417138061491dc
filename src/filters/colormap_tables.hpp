#pragma once
// Sampled colour tables of the filters module (private): every third entry of matplotlib's
// viridis, plasma and inferno tables (CC0), sRGB components in [0, 1] at t = k / (entries - 1).

#include <cstddef>

namespace isoforge::colormap_tables {

inline constexpr std::size_t kSampledEntries = 86;

extern const double kViridis[kSampledEntries][3];
extern const double kPlasma[kSampledEntries][3];
extern const double kInferno[kSampledEntries][3];

}  // namespace isoforge::colormap_tables
