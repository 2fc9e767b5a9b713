#include "mesh/initial_mesh.hpp"
#include <stdexcept>
namespace lhr {
double default_max_edge(const Scene&) { throw std::logic_error("not implemented"); }
TriMesh mesh_surface(const Surface&, const MeshingOptions&) { throw std::logic_error("not implemented"); }
}  // namespace lhr
