// placeholder: implemented in a following commit
#include "isoforge/io/mesh_formats.hpp"
namespace isoforge {
void write_obj(const PolyData&, const std::filesystem::path&) { throw Error("not yet"); }
PolyData read_off(const std::filesystem::path&) { throw Error("not yet"); }
PolyData read_off(std::span<const std::byte>, std::string_view) { throw Error("not yet"); }
void write_off(const PolyData&, const std::filesystem::path&) { throw Error("not yet"); }
}
