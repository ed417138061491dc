// Uses the installed isoforge: builds a dataset, writes it, reads it back and checks it, and
// reads a real file given on the command line. Exit status 0 only if everything matches.
#include <isoforge/core/dataset.hpp>
#include <isoforge/io/io.hpp>
#include <isoforge/version.hpp>

#include <cstdio>
#include <filesystem>

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: consumer DATA_FILE SCRATCH_DIR\n");
    return 2;
  }
  try {
    isoforge::ImageData img;
    img.dims = {4, 3, 2};
    img.spacing = {0.5, 0.5, 0.5};
    isoforge::DataArray s("s", isoforge::ScalarType::Float32, 1, img.num_points());
    for (std::size_t i = 0; i < img.num_points(); ++i) s.set(i, 0, static_cast<double>(i));
    img.point_data.add(std::move(s), isoforge::AttributeRole::Scalars);
    const auto path = std::filesystem::path(argv[2]) / "consumer.vti";
    isoforge::write(img, path);
    const isoforge::Dataset back = isoforge::read(path);
    if (!(std::get<isoforge::ImageData>(back) == img)) {
      std::fprintf(stderr, "round trip through %s changed the data\n", path.c_str());
      return 1;
    }
    const isoforge::Dataset real = isoforge::read(argv[1]);
    std::printf("isoforge %s: %s has %zu points and %zu cells\n",
                std::string(isoforge::kVersion).c_str(), argv[1], isoforge::num_points(real),
                isoforge::num_cells(real));
    return isoforge::num_points(real) > 0 ? 0 : 1;
  } catch (const isoforge::Error& e) {
    std::fprintf(stderr, "consumer: %s\n", e.what());
    return 1;
  }
}
