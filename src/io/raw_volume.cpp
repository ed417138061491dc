// placeholder: implemented in a following commit
#include "isoforge/io/raw_volume.hpp"
namespace isoforge {
ImageData read_nrrd(const std::filesystem::path&) { throw Error("not yet"); }
ImageData read_nrrd(std::span<const std::byte>, std::string_view, const std::filesystem::path&) { throw Error("not yet"); }
ImageData read_metaimage(const std::filesystem::path&) { throw Error("not yet"); }
ImageData read_metaimage(std::span<const std::byte>, std::string_view, const std::filesystem::path&) { throw Error("not yet"); }
}
