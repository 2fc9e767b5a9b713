#include "mesh/coarsen.hpp"

#include <algorithm>
#include <array>
#include <vector>

namespace lhr {

namespace {

// Botsch & Kobbelt (2004): collapse edges shorter than 4/5 of the target
// unless that makes one longer than 4/3 of it.
constexpr double kLowFraction = 4.0 / 5.0;
constexpr double kHighFraction = 4.0 / 3.0;
// Sweeping in mesh order rather than shortest first, a vertex could gather
// many rings; capping its valence bounds the work per collapse and keeps the
// triangles' angles away from zero for the remeshing that follows.
constexpr std::size_t kMaxValence = 12;
// A triangle may turn by at most 60° in a collapse (across unconstrained
// edges the surface bends by under 2°, so only a fold turns one that far).
constexpr double kMinTurnCosine = 0.5;
// No triangle may get a vertex closer than this fraction of its longest edge
// to the opposite edge's line (as mesh/curved_mesh.cpp checks its output).
constexpr double kDegenerateHeight = 1e-6;

bool on_a_line(const TriMesh& mesh, TriMesh::VertexHandle v, const CoarseningConstraints& c) {
  for (const auto e : mesh.ve_range(v)) {
    if (mesh.property(c.constrained_edge, e) != 0) return true;
  }
  return false;
}

// Whether moving v0 onto v1 keeps every triangle around v0 that survives
// (those without v1) facing the same way and well shaped, and every edge to
// v1 at most `high_sq` long.
bool collapse_keeps_shape(const TriMesh& mesh, TriMesh::HalfedgeHandle h, double high_sq) {
  const TriMesh::VertexHandle v0 = mesh.from_vertex_handle(h), v1 = mesh.to_vertex_handle(h);
  const Vec3& p1 = mesh.point(v1);
  for (const auto u : mesh.vv_range(v0)) {
    if (u != v1 && (mesh.point(u) - p1).sqrnorm() > high_sq) return false;
  }
  for (const auto f : mesh.vf_range(v0)) {
    std::array<Vec3, 3> before, after;
    int k = 0;
    bool has_v1 = false;
    for (const auto v : mesh.fv_range(f)) {
      has_v1 = has_v1 || v == v1;
      before[k] = mesh.point(v);
      after[k] = v == v0 ? p1 : before[k];
      ++k;
    }
    if (has_v1) continue;  // removed by the collapse
    const Vec3 n_before = OpenMesh::cross(before[1] - before[0], before[2] - before[0]);
    const Vec3 n_after = OpenMesh::cross(after[1] - after[0], after[2] - after[0]);
    const double longest_sq = std::max({(after[1] - after[0]).sqrnorm(), (after[2] - after[1]).sqrnorm(),
                                        (after[0] - after[2]).sqrnorm()});
    if (!(n_after.norm() > kDegenerateHeight * longest_sq)) return false;
    if (!(OpenMesh::dot(n_before, n_after) > kMinTurnCosine * n_before.norm() * n_after.norm())) return false;
  }
  return true;
}

}  // namespace

std::size_t collapse_short_edges(TriMesh& mesh, double target, const CoarseningConstraints& constraints,
                                 MeshingCheckpoint& checkpoint) {
  const double low_sq = kLowFraction * kLowFraction * target * target;
  const double high_sq = kHighFraction * kHighFraction * target * target;
  std::vector<TriMesh::VertexHandle> ring;
  std::size_t collapses = 0;
  for (std::size_t i = 0; i < mesh.n_halfedges(); ++i) {
    checkpoint.tick();
    const TriMesh::HalfedgeHandle h(static_cast<int>(i));
    const TriMesh::EdgeHandle e = mesh.edge_handle(h);
    if (mesh.status(e).deleted()) continue;
    const TriMesh::VertexHandle v0 = mesh.from_vertex_handle(h), v1 = mesh.to_vertex_handle(h);
    if ((mesh.point(v1) - mesh.point(v0)).sqrnorm() >= low_sq) continue;
    if (mesh.property(constraints.fixed_vertex, v0) != 0) continue;
    // A vertex of a line moves only along it; any other vertex anywhere.
    const bool along_a_line = mesh.property(constraints.constrained_edge, e) != 0;
    if (!along_a_line && on_a_line(mesh, v0, constraints)) continue;
    if (mesh.valence(v0) + mesh.valence(v1) > kMaxValence + 4) continue;
    if (!mesh.is_collapse_ok(h) || !collapse_keeps_shape(mesh, h, high_sq)) continue;
    // A line through v0 must run through v1 afterwards, and the collapse
    // merges each removed triangle's edges to v0 and v1 into one, keeping
    // either: the flags of both ends' edges are set again on what is left.
    ring.clear();
    for (const auto v : {v0, v1}) {
      for (const auto out : mesh.voh_range(v)) {
        if (mesh.property(constraints.constrained_edge, mesh.edge_handle(out)) != 0) {
          ring.push_back(mesh.to_vertex_handle(out));
        }
      }
    }
    mesh.collapse(h);
    for (const TriMesh::VertexHandle u : ring) {
      if (u == v1 || u == v0) continue;
      const TriMesh::HalfedgeHandle kept = mesh.find_halfedge(v1, u);
      if (kept.is_valid()) mesh.property(constraints.constrained_edge, mesh.edge_handle(kept)) = 1;
    }
    ++collapses;
  }
  return collapses;
}

}  // namespace lhr
