// Fig. 1.24a: the pixels of a 40 x 30 image (spacing 0.05 from (-1, -0.75)) lying inside the
// ellipse (x / 0.8)^2 + (y / 0.5)^2 = 1, selected by the quadric as an implicit function.

#include <fmt/core.h>

#include "figure.hpp"
#include "isoforge/contour/contour.hpp"
#include "isoforge/core/grid_spec.hpp"
#include "isoforge/filters/surface.hpp"
#include "isoforge/implicit/sample.hpp"
#include "isoforge/implicit/select.hpp"

namespace isoforge::cli::figures {

Output fig_1_24a(const Context&) {
  ImageData img;
  img.dims = {41, 31, 1};
  img.origin = {-1, -0.75, 0};
  img.spacing = {0.05, 0.05, 1};
  const ImplicitFunction ellipse =
      ImplicitFunction::quadric({1 / 0.64, 1 / 0.25, 0, 0, 0, 0, 0, 0, 0, -1});
  const UnstructuredGrid selected = extract_cells(img, ellipse);
  // Independent count: pixels whose four corners all satisfy the quadric.
  std::size_t expected = 0;
  for (int j = 0; j < 30; ++j) {
    for (int i = 0; i < 40; ++i) {
      bool inside = true;
      for (int c = 0; c < 4; ++c) {
        const double x = -1 + 0.05 * (i + (c & 1)), y = -0.75 + 0.05 * (j + (c >> 1));
        inside = inside && x * x / 0.64 + y * y / 0.25 - 1 <= 0;
      }
      expected += inside ? 1 : 0;
    }
  }
  // The ellipse itself, contoured on a finer sampling, for the picture.
  Bounds b;
  b.min = {-1, -0.75, 0};
  b.max = {1, 0.75, 0};
  const ImageData fine = sample_image(ellipse, GridSpec::from_bounds(b, {201, 151, 1}));
  const PolyData outline = contour(fine, {}).output;
  const PolyData all = extract_surface(img).output;
  Output out;
  out.datasets.emplace_back("image", img);
  out.datasets.emplace_back("selected_pixels", selected);
  out.datasets.emplace_back("ellipse", outline);
  out.meshes.push_back({"image (wireframe)", wireframe(all), "", Colormap::Rainbow, std::nullopt,
                        {150, 150, 150, 255}});
  out.meshes.push_back({"selected pixels", translated(extract_surface(selected).output, {0, 0, 0.002}),
                        "", Colormap::Rainbow, std::nullopt, {70, 130, 220, 255}});
  out.meshes.push_back({"ellipse", translated(outline, {0, 0, 0.004}), "", Colormap::Rainbow,
                        std::nullopt, {250, 200, 40, 255}});
  out.counts = fmt::format("{} of {} pixels selected", selected.num_cells(), 40 * 30);
  out.check = fmt::format("all 4 corners inside: {} pixels counted independently", expected);
  out.ok = selected.num_cells() == expected && expected > 0;
  return out;
}

}  // namespace isoforge::cli::figures
