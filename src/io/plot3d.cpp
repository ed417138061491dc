// placeholder: implemented in a following commit
#include "isoforge/io/plot3d.hpp"
namespace isoforge {
StructuredGrid read_plot3d(const std::filesystem::path&, const std::filesystem::path&, const Plot3dOptions&) { throw Error("not yet"); }
StructuredGrid read_plot3d(std::span<const std::byte>, std::string_view, std::span<const std::byte>, std::string_view, const Plot3dOptions&) { throw Error("not yet"); }
}
