#pragma once
// Invariant checks (docs/design.md §6): conforming meshes as files hold them;
// the violations they report (surface hierarchies: mesh/hierarchy_check.hpp).

#include <string>
#include <vector>

#include "mesh/types.hpp"

namespace lhr {

// A mesh exactly as a file holds it: no merging, no repair.
struct RawMesh {
  std::vector<Vec3> points;
  std::vector<std::vector<int>> faces;
  std::vector<Rgb> radiance;  // per vertex when the file has it, else empty
  std::vector<double> radiance_stderr;  // per vertex when the file has it (a path-traced reference), else empty
};

struct Violation {
  std::string kind;   // short id: "t-junction", "orientation", "non-manifold-edge", ...
  std::string where;  // e.g. "face 12", "edge (3,7)", "vertex 5"
  std::string detail;
};

struct ConformingCheckOptions {
  // Relative to the mesh's bounding-box diagonal: distance under which a
  // vertex is taken to lie on an edge (T-junction) or faces are degenerate.
  double relative_tolerance = 1e-9;
};

// Manifold edges and vertices, consistent orientation, no degenerate or
// duplicated faces, indices in range, finite coordinates and values, and no
// T-junction cracks: no vertex lies inside an edge of its own connected
// component that it is not an end of. Components (faces linked through
// shared vertex indices) may touch geometrically: surfaces meet that way.
std::vector<Violation> check_conforming_mesh(const RawMesh& mesh,
                                             const ConformingCheckOptions& options = {});

// One line per violation, for reports.
std::string format_violation(const Violation& v);

}  // namespace lhr
