#pragma once
/// \file
/// The sRGB transfer functions (IEC 61966-2-1): 8-bit colours are sRGB-encoded; blending,
/// colour-map interpolation and glTF's COLOR_0 work in linear light.

#include <cmath>

namespace isoforge {

/// Linear-light value of an sRGB-encoded channel, both in [0, 1].
inline double srgb_to_linear(double c) {
  return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
}

/// sRGB-encoded value of a linear-light channel, both in [0, 1].
inline double linear_to_srgb(double c) {
  return c <= 0.0031308 ? 12.92 * c : 1.055 * std::pow(c, 1 / 2.4) - 0.055;
}

}  // namespace isoforge
