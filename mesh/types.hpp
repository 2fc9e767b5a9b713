#pragma once
// Geometry types shared by every lhr library.

#include <OpenMesh/Core/Geometry/VectorT.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>

#include <string>

#include "mesh/rgb.hpp"

namespace lhr {

using Vec3 = OpenMesh::Vec3d;

struct MeshTraits : public OpenMesh::DefaultTraits {
  using Point = OpenMesh::Vec3d;
  using Normal = OpenMesh::Vec3d;
};

// Half-edge triangle mesh used for initial meshes, hierarchies and export.
using TriMesh = OpenMesh::TriMesh_ArrayKernelT<MeshTraits>;

// "(x, y, z)" for messages that name a point.
// Built by appends: GCC 12 reports a false -Wrestrict for "(" + std::string.
inline std::string describe_point(const Vec3& p) {
  std::string text(1, '(');
  text.append(std::to_string(p[0])).append(", ").append(std::to_string(p[1])).append(", ");
  text.append(std::to_string(p[2])).push_back(')');
  return text;
}

}  // namespace lhr
