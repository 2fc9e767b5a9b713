#include "mesh/curved_mesh.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>
#include <vector>

#include "mesh/cgal_meshing.hpp"
#include "mesh/meshing_checkpoint.hpp"

namespace lhr {

namespace {

// No remeshed triangle may have a vertex closer than this fraction of its
// longest edge to the line through the opposite edge.
constexpr double kDegenerateHeight = 1e-6;

}  // namespace

TriMesh mesh_curved(const Surface& surface, const MeshingOptions& options) {
  const double h = options.max_edge;
  TriMesh mesh;
  std::vector<TriMesh::VertexHandle> handle(surface.points.size());
  for (std::size_t p = 0; p < surface.polygons.size(); ++p) {
    const auto& poly = surface.polygons[p];
    for (int i : poly) {
      if (!handle[i].is_valid()) handle[i] = mesh.add_vertex(surface.points[i]);
    }
    for (std::size_t i = 1; i + 1 < poly.size(); ++i) {
      const auto fh = mesh.add_face(handle[poly[0]], handle[poly[i]], handle[poly[i + 1]]);
      if (!fh.is_valid()) {
        throw std::runtime_error("polygon " + std::to_string(p) +
                                 " makes the surface non-manifold or flips its orientation");
      }
    }
  }
  for (const auto f : mesh.faces()) {
    if (!(mesh.calc_face_normal(f).norm() > 0.0)) {
      throw std::runtime_error("has a zero-area polygon; remove it or merge its vertices");
    }
  }
  std::vector<TriMesh::VertexHandle> fixed;
  for (const auto& [a, b] : surface.seam_edges) {
    fixed.push_back(handle.at(a));
    fixed.push_back(handle.at(b));
  }
  MeshingCheckpoint checkpoint(options.checkpoint);
  checkpoint();
  remesh_isotropic(mesh, h, fixed, checkpoint);
  checkpoint();
  mesh.garbage_collection();
  // CGAL's Euler operations do not keep OpenMesh's invariant that a boundary
  // vertex's outgoing halfedge is a boundary one; is_boundary(v) relies on it.
  for (const auto v : mesh.vertices()) mesh.adjust_outgoing_halfedge(v);
  for (const auto e : mesh.edges()) {
    if (mesh.calc_edge_length(e) > h * (1.0 + 1e-9)) {
      throw std::runtime_error("remeshing left an edge longer than the maximum edge length");
    }
  }
  // Embree and the form factors need a normal on every triangle.
  for (const auto f : mesh.faces()) {
    double longest = 0.0;
    for (const auto he : mesh.fh_range(f)) longest = std::max(longest, mesh.calc_edge_length(he));
    if (!(2.0 * mesh.calc_face_area(f) > kDegenerateHeight * longest * longest)) {
      throw std::runtime_error("remeshing left a degenerate triangle; give a smaller --max-edge");
    }
  }
  if (mesh.n_faces() == 0) throw std::runtime_error("remeshing produced no triangles");
  return mesh;
}

}  // namespace lhr
