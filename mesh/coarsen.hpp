#pragma once
// Coarsening a curved surface far finer than its target before CGAL's
// isotropic remeshing (docs/design.md §4, "Curved surfaces"): edge collapses
// alone, in the mesh's own order, so the work per input triangle is bounded
// and memory is walked in order.

#include <cstddef>

#include "mesh/meshing_checkpoint.hpp"
#include "mesh/types.hpp"

namespace lhr {

// What must survive coarsening, as flags on the mesh (non-zero = set):
// constrained edges (the border and the bends) stay lines of the mesh,
// collapsed only along themselves; fixed vertices stay.
struct CoarseningConstraints {
  OpenMesh::EPropHandleT<unsigned char> constrained_edge;
  OpenMesh::VPropHandleT<unsigned char> fixed_vertex;
};

// One sweep over the half-edges: each edge shorter than 4/5 of `target` is
// collapsed into its far end when no edge then grows past 4/3 of `target`
// (the bounds of Botsch & Kobbelt 2004, as CGAL's remeshing), no triangle
// turns over or degenerates, the topology stays manifold, and the
// constraints hold. Every remaining vertex is an input vertex, in place.
// Needs the mesh's status attributes; leaves deleted elements for garbage
// collection. Returns the number of collapses.
std::size_t collapse_short_edges(TriMesh& mesh, double target, const CoarseningConstraints& constraints,
                                 MeshingCheckpoint& checkpoint);

}  // namespace lhr
