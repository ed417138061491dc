#pragma once
/// \file
/// Tuning constants of the robust losses, shared by primitive fitting and mesh refinement.

namespace isoforge::fit_detail {

inline constexpr double kMadToSigma = 1.4826;  // σ of a normal distribution from its median |r|
inline constexpr double kHuberK = 1.345;       // 95% efficiency at the normal distribution
inline constexpr double kCauchyK = 2.385;      // likewise for Cauchy

}  // namespace isoforge::fit_detail
