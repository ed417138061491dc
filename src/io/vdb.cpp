// placeholder: implemented in a following commit
#include "isoforge/io/vdb.hpp"
namespace isoforge {
void ensure_openvdb_initialized() {}
openvdb::FloatGrid::Ptr read_vdb_grid(const std::filesystem::path&, std::string_view) { throw Error("not yet"); }
std::vector<VdbGridInfo> inspect_vdb(const std::filesystem::path&) { throw Error("not yet"); }
void write_vdb(const std::vector<openvdb::GridBase::Ptr>&, const std::filesystem::path&) { throw Error("not yet"); }
void write_vdb(const openvdb::FloatGrid&, const std::filesystem::path&) { throw Error("not yet"); }
ImageData vdb_to_image(const openvdb::FloatGrid&, std::size_t) { throw Error("not yet"); }
openvdb::FloatGrid::Ptr image_to_vdb(const ImageData&, std::string_view, float, float) { throw Error("not yet"); }
}
