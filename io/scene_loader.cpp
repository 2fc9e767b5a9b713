#include "io/scene_loader.hpp"
namespace lhr {
LoadResult load_scene(const std::filesystem::path& p, const LoadOptions&) { throw InputError(p, "not implemented"); }
PolygonSoup load_polygon_soup(const std::filesystem::path& p) { throw InputError(p, "not implemented"); }
}  // namespace lhr
