#pragma once
// The invariants of a surface hierarchy while a solver refines it
// (docs/design.md §6), reported as violations (mesh/validate.hpp).

#include <vector>

#include "mesh/hierarchy.hpp"
#include "mesh/validate.hpp"

namespace lhr {

// Restricted property (leaves sharing an edge differ by <= 1 level),
// parent/child consistency, midpoints shared and placed at edge midpoints,
// T-vertex bookkeeping.
std::vector<Violation> check_hierarchy(const SurfaceHierarchy& hierarchy);

}  // namespace lhr
