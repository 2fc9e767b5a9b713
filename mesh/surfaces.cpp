#include "mesh/surfaces.hpp"
#include <stdexcept>
namespace lhr {
SurfaceSplit split_into_surfaces(const PolygonSoup&, double) { throw std::logic_error("not implemented"); }
}  // namespace lhr
