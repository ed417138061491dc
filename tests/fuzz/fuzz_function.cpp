// Fuzz target: the function expression language (parse_implicit, the CLI's --function), then the
// parsed function at a few points. Only isoforge::Error may escape parsing; evaluation must not
// crash, and two properties are checked (a violation traps, which libFuzzer reports):
//   - printing reads back: parse_implicit(f.to_string()) gives bit-identical values;
//   - pruned evaluation (sample_image skips boolean branches by their bounds) gives the same
//     values as evaluating the whole tree at each point.
// Values that are not finite (overflowing parameters) are compared only for being not finite.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "isoforge/implicit/parse.hpp"
#include "isoforge/implicit/sample.hpp"

namespace {

bool same(double a, double b) {
  if (!std::isfinite(a) || !std::isfinite(b)) return !std::isfinite(a) && !std::isfinite(b);
  return a == b;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace isoforge;
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  ImplicitFunction f = ImplicitFunction::sphere({0, 0, 0}, 1);
  try {
    f = parse_implicit(text);
  } catch (const Error&) {
    return 0;  // rejecting bad input with a clear error is the expected outcome
  }
  const ImplicitFunction back = parse_implicit(f.to_string());
  const Vec3 points[] = {{0, 0, 0}, {0.5, -0.25, 1}, {-3, 2, 0.125}, {1e3, -1e3, 7}};
  for (const Vec3& p : points) {
    const double v = f.value(p);
    if (!same(v, back.value(p))) __builtin_trap();
    (void)f.gradient(p);
  }
  const Bounds box{{-1.5, -1, -0.5}, {1.5, 1, 2}};
  (void)f.bound(box);
  const GridSpec grid = GridSpec::from_bounds(box, {5, 4, 6});
  SampleOptions o;
  o.type = ScalarType::Float64;
  const ImageData img = sample_image(f, grid, o);
  const auto values = img.point_data.get("F").values<double>();
  std::size_t i = 0;
  for (Index k = 0; k < grid.dims[2]; ++k)
    for (Index j = 0; j < grid.dims[1]; ++j)
      for (Index x = 0; x < grid.dims[0]; ++x, ++i) {
        const Vec3 p{grid.coordinate(0, x), grid.coordinate(1, j), grid.coordinate(2, k)};
        if (!same(values[i], f.value(p))) __builtin_trap();
      }
  return 0;
}
