#pragma once
// Geometry types shared by every lhr library.

#include <OpenMesh/Core/Geometry/VectorT.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>

#include "mesh/rgb.hpp"

namespace lhr {

using Vec3 = OpenMesh::Vec3d;

struct MeshTraits : public OpenMesh::DefaultTraits {
  using Point = OpenMesh::Vec3d;
  using Normal = OpenMesh::Vec3d;
};

// Half-edge triangle mesh used for initial meshes, hierarchies and export.
using TriMesh = OpenMesh::TriMesh_ArrayKernelT<MeshTraits>;

}  // namespace lhr
