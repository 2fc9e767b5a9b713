#include "mesh/validate.hpp"
#include <stdexcept>
namespace lhr {
std::vector<Violation> check_conforming_mesh(const RawMesh&, const ConformingCheckOptions&) { throw std::logic_error("not implemented"); }
std::vector<Violation> check_hierarchy(const SurfaceHierarchy&) { throw std::logic_error("not implemented"); }
std::string format_violation(const Violation& v) { return v.kind; }
}  // namespace lhr
