#pragma once
// A curved surface's initial mesh (docs/design.md §4, "Initial meshing"):
// isotropic remeshing to the minimum density h, the border, seams and bends
// of the input kept as lines of the mesh.

#include "mesh/initial_mesh.hpp"
#include "mesh/scene.hpp"
#include "mesh/types.hpp"

namespace lhr {

// Faces counter-clockwise seen from the surface's front. Throws
// std::runtime_error saying what is wrong (mesh_surface adds the surface's
// name); what options.checkpoint throws comes out as CheckpointThrew
// (mesh/meshing_checkpoint.hpp).
TriMesh mesh_curved(const Surface& surface, const MeshingOptions& options);

}  // namespace lhr
