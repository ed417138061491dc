// placeholder: implemented in a following commit
#include "isoforge/io/mesh_formats.hpp"
namespace isoforge {
PolyData read_ply(const std::filesystem::path&) { throw Error("not yet"); }
PolyData read_ply(std::span<const std::byte>, std::string_view) { throw Error("not yet"); }
void write_ply(const PolyData&, const std::filesystem::path&, const PlyWriteOptions&) { throw Error("not yet"); }
}
