// placeholder: implemented in a following commit
#include "isoforge/io/vtk_xml.hpp"
namespace isoforge {
Dataset read_vtk_xml(const std::filesystem::path&) { throw Error("not yet"); }
Dataset read_vtk_xml(std::span<const std::byte>, std::string_view) { throw Error("not yet"); }
std::string_view vtk_xml_extension(const Dataset&) { return ".vtk"; }
void write_vtk_xml(const Dataset&, const std::filesystem::path&, const VtkXmlWriteOptions&) { throw Error("not yet"); }
void write_vtk_xml(const Dataset&, std::ostream&, const VtkXmlWriteOptions&) { throw Error("not yet"); }
}
