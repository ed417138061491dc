#pragma once
/// \file
/// Explicit one-step integrators of autonomous ODEs y' = f(y), shared by trajectory densities
/// (the Lorenz attractor) and streamlines. `State` is any type with `+`, `-` and `* double`
/// (e.g. `Vec3`); `f` any callable `State f(const State&)`. Templates, so the right-hand side
/// inlines into the integration loop.

namespace isoforge {

/// One explicit midpoint (second-order Runge–Kutta) step of size h.
template <class F, class State>
[[nodiscard]] inline State rk2_step(F&& f, const State& y, double h) {
  const State k1 = f(y);
  return y + f(y + k1 * (0.5 * h)) * h;
}

/// One classical fourth-order Runge–Kutta step of size h (Kutta 1901; Hairer, Nørsett & Wanner,
/// *Solving ODEs I*, II.1).
template <class F, class State>
[[nodiscard]] inline State rk4_step(F&& f, const State& y, double h) {
  const State k1 = f(y);
  const State k2 = f(y + k1 * (0.5 * h));
  const State k3 = f(y + k2 * (0.5 * h));
  const State k4 = f(y + k3 * h);
  return y + (k1 + k2 * 2.0 + k3 * 2.0 + k4) * (h / 6.0);
}

}  // namespace isoforge
