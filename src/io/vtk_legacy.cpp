// placeholder: implemented in a following commit
#include "isoforge/io/vtk_legacy.hpp"
namespace isoforge {
Dataset read_vtk_legacy(const std::filesystem::path&) { throw Error("not yet"); }
Dataset read_vtk_legacy(std::span<const std::byte>, std::string_view) { throw Error("not yet"); }
void write_vtk_legacy(const Dataset&, const std::filesystem::path&, const VtkLegacyWriteOptions&) { throw Error("not yet"); }
void write_vtk_legacy(const Dataset&, std::ostream&, const VtkLegacyWriteOptions&) { throw Error("not yet"); }
}
