// The restricted triangle quadtree (paper §3, docs/design.md §4 "Hierarchy"): splits,
// shared midpoints, forced splits, T-vertices and the conforming export.

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <map>
#include <numbers>
#include <random>
#include <set>
#include <utility>
#include <vector>

#include "mesh/hierarchy.hpp"
#include "mesh/hierarchy_check.hpp"
#include "mesh/validate.hpp"
#include "radiosity/meshed_scene.hpp"
#include "scene_fixtures.hpp"

namespace lhr {
namespace {

TriMesh make_mesh(const std::vector<Vec3>& points, const std::vector<std::array<int, 3>>& faces) {
  TriMesh mesh;
  std::vector<TriMesh::VertexHandle> vh;
  for (const auto& p : points) vh.push_back(mesh.add_vertex(p));
  for (const auto& f : faces) {
    const auto fh = mesh.add_face(vh[f[0]], vh[f[1]], vh[f[2]]);
    EXPECT_TRUE(fh.is_valid());
  }
  return mesh;
}

TriMesh single_triangle() { return make_mesh({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {{{0, 1, 2}}}); }

// Unit square cut along the diagonal (0,2): face 0 = (0,1,2), face 1 = (0,2,3).
TriMesh two_triangles() {
  return make_mesh({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}, {{{0, 1, 2}}, {{0, 2, 3}}});
}

Vec3 hex_point(int i) {
  const double a = std::numbers::pi / 3.0 * (i - 1);
  return {std::cos(a), std::sin(a), 0.0};
}

// Centre vertex 0, ring vertices 1..6; face i = (0, i+1, i+2 wrapped).
TriMesh hexagon_fan() {
  std::vector<Vec3> points = {{0, 0, 0}};
  for (int i = 1; i <= 6; ++i) points.push_back(hex_point(i));
  std::vector<std::array<int, 3>> faces;
  for (int i = 1; i <= 6; ++i) faces.push_back({0, i, i % 6 + 1});
  return make_mesh(points, faces);
}

constexpr int kGrid = 10;

// kGrid x kGrid unit cells in the z = 0 plane, each cut into two right triangles.
TriMesh grid_mesh() {
  std::vector<Vec3> points;
  for (int j = 0; j <= kGrid; ++j) {
    for (int i = 0; i <= kGrid; ++i) points.push_back({double(i), double(j), 0.0});
  }
  auto id = [](int i, int j) { return j * (kGrid + 1) + i; };
  std::vector<std::array<int, 3>> faces;
  for (int j = 0; j < kGrid; ++j) {
    for (int i = 0; i < kGrid; ++i) {
      faces.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      faces.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  }
  return make_mesh(points, faces);
}

std::set<VertexId> corner_set(const SurfaceHierarchy& h, NodeId n) {
  const auto& c = h.corners(n);
  return {c[0], c[1], c[2]};
}

// Twice the signed area of (a,b,c) projected on z = 0.
double signed_area2(const Vec3& a, const Vec3& b, const Vec3& c) {
  return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
}

// The leaf whose triangle (z = 0 meshes) strictly contains p.
NodeId leaf_containing(const SurfaceHierarchy& h, const Vec3& p) {
  NodeId found = kNoNode;
  for (const NodeId n : h.leaves()) {
    const auto& c = h.corners(n);
    const Vec3 a = h.point(c[0]), b = h.point(c[1]), d = h.point(c[2]);
    if (signed_area2(a, b, p) > 0 && signed_area2(b, d, p) > 0 && signed_area2(d, a, p) > 0) {
      EXPECT_EQ(found, kNoNode) << "leaves overlap at a point";
      found = n;
    }
  }
  return found;
}

std::vector<std::array<int, 3>> face_list(const TriMesh& mesh) {
  std::vector<std::array<int, 3>> out;
  for (const auto fh : mesh.faces()) {
    std::array<int, 3> f{};
    int k = 0;
    for (const auto vh : mesh.fv_range(fh)) f[k++] = vh.idx();
    EXPECT_EQ(k, 3);
    out.push_back(f);
  }
  return out;
}

// Same triangle with the same orientation: equal up to cyclic rotation.
bool same_oriented_triangle(std::array<int, 3> a, const std::array<int, 3>& b) {
  for (int r = 0; r < 3; ++r) {
    if (a == b) return true;
    std::rotate(a.begin(), a.begin() + 1, a.end());
  }
  return false;
}

std::string violations_text(const std::vector<Violation>& violations) {
  std::string s;
  for (std::size_t i = 0; i < violations.size() && i < 10; ++i) {
    s += violations[i].kind + " @ " + violations[i].where + ": " + violations[i].detail + "\n";
  }
  return s;
}

TEST(Hierarchy, RootsFollowInitialFaces) {
  const TriMesh initial = grid_mesh();
  const SurfaceHierarchy h(initial);
  EXPECT_EQ(h.num_roots(), initial.n_faces());
  EXPECT_EQ(h.num_nodes(), initial.n_faces());
  EXPECT_EQ(h.num_leaves(), initial.n_faces());
  EXPECT_EQ(h.num_vertices(), initial.n_vertices());
  EXPECT_EQ(h.max_level(), 0);
  for (const auto fh : initial.faces()) {
    const NodeId r = h.root(fh.idx());
    EXPECT_EQ(h.level(r), 0);
    EXPECT_EQ(h.parent(r), kNoNode);
    EXPECT_TRUE(h.is_leaf(r));
    EXPECT_EQ(h.root_face(r), fh.idx());
    std::set<VertexId> face_vertices;
    for (const auto vh : initial.fv_range(fh)) face_vertices.insert(vh.idx());
    EXPECT_EQ(corner_set(h, r), face_vertices);
    const auto& c = h.corners(r);
    EXPECT_GT(signed_area2(h.point(c[0]), h.point(c[1]), h.point(c[2])), 0.0) << "root " << r << " not ccw";
  }
  EXPECT_TRUE(h.t_vertices().empty());
  EXPECT_TRUE(check_hierarchy(h).empty());
}

TEST(Hierarchy, SingleTriangleSplitFollowsDocumentedChildren) {
  SurfaceHierarchy h(single_triangle());
  EXPECT_EQ(h.split(0), std::vector<NodeId>{0});
  ASSERT_FALSE(h.is_leaf(0));
  EXPECT_EQ(h.num_nodes(), 5u);
  EXPECT_EQ(h.num_leaves(), 4u);
  EXPECT_EQ(h.num_vertices(), 6u);
  EXPECT_EQ(h.max_level(), 1);
  const auto v = h.corners(0);
  const VertexId m01 = h.midpoint(v[0], v[1]), m12 = h.midpoint(v[1], v[2]), m20 = h.midpoint(v[2], v[0]);
  for (const VertexId m : {m01, m12, m20}) {
    ASSERT_NE(m, kNoVertex);
    EXPECT_EQ(h.vertex_level(m), 1);
    EXPECT_FALSE(h.is_t_vertex(m)) << "boundary midpoints are not T-vertices";
  }
  EXPECT_EQ(h.midpoint(v[1], v[0]), m01);
  EXPECT_EQ(h.point(m01), 0.5 * (h.point(v[0]) + h.point(v[1])));
  const std::array<std::array<VertexId, 3>, 4> expected = {{
      {v[0], m01, m20},
      {m01, v[1], m12},
      {m20, m12, v[2]},
      {m12, m20, m01},
  }};
  for (int i = 0; i < 4; ++i) {
    const NodeId c = h.child(0, i);
    EXPECT_EQ(h.corners(c), expected[i]);
    EXPECT_EQ(h.parent(c), 0);
    EXPECT_EQ(h.child_index(c), i);
    EXPECT_EQ(h.level(c), 1);
    EXPECT_EQ(h.root_face(c), 0);
  }
  // Splitting a node that is not a leaf does nothing.
  EXPECT_TRUE(h.split(0).empty());
  EXPECT_EQ(h.num_nodes(), 5u);
  EXPECT_THROW(h.split(99), std::out_of_range);
  EXPECT_THROW(h.split(-1), std::out_of_range);
  EXPECT_TRUE(check_hierarchy(h).empty()) << violations_text(check_hierarchy(h));
  EXPECT_EQ(h.conforming_mesh().mesh.n_faces(), 4u);
}

TEST(Hierarchy, SharedEdgeMidpointIsTVertexUntilNeighbourSplits) {
  SurfaceHierarchy h(two_triangles());
  EXPECT_TRUE(h.neighbor(0, 0) == 1 || h.neighbor(0, 1) == 1 || h.neighbor(0, 2) == 1);
  EXPECT_EQ(h.split(0), std::vector<NodeId>{0});
  EXPECT_EQ(h.num_vertices(), 4u + 3u);
  EXPECT_EQ(h.num_nodes(), 2u + 4u);
  EXPECT_EQ(h.nodes_at_level(1).size(), 4u);
  EXPECT_EQ(h.num_leaves(), 5u);

  const VertexId m = h.midpoint(0, 2);
  ASSERT_NE(m, kNoVertex);
  EXPECT_EQ(h.point(m), Vec3(0.5, 0.5, 0.0));
  EXPECT_TRUE(h.is_t_vertex(m));
  EXPECT_EQ(h.t_vertices(), std::vector<VertexId>{m});
  EXPECT_EQ(h.midpoint(0, 3), kNoVertex);
  EXPECT_EQ(h.midpoint(2, 3), kNoVertex);

  // Root 0 stays root 1's same-level neighbour; being split, it is no leaf
  // neighbour any more.
  int shared = -1;
  for (int k = 0; k < 3; ++k) {
    if (h.neighbor(1, k) == 0) shared = k;
  }
  ASSERT_GE(shared, 0);
  EXPECT_EQ(h.coarser_or_equal_leaf_neighbor(1, shared), kNoNode);
  // The children of root 0 on the diagonal see root 1 as their coarser leaf.
  const NodeId child_near_0 = leaf_containing(h, {0.2, 0.1, 0.0});
  ASSERT_NE(child_near_0, kNoNode);
  EXPECT_EQ(h.level(child_near_0), 1);
  int on_diagonal = -1;
  for (int k = 0; k < 3; ++k) {
    const auto& c = h.corners(child_near_0);
    if (std::set<VertexId>{c[k], c[(k + 1) % 3]} == std::set<VertexId>{0, m}) on_diagonal = k;
  }
  ASSERT_GE(on_diagonal, 0);
  EXPECT_EQ(h.neighbor(child_near_0, on_diagonal), kNoNode);
  EXPECT_FALSE(h.is_boundary_edge(child_near_0, on_diagonal));
  EXPECT_EQ(h.coarser_or_equal_leaf_neighbor(child_near_0, on_diagonal), 1);

  // Export: root 1 is cut through the T-vertex into 2 triangles.
  const ConformingMesh cm = h.conforming_mesh();
  EXPECT_EQ(cm.mesh.n_faces(), 4u + 2u);
  EXPECT_EQ(cm.mesh.n_vertices(), 7u);
  EXPECT_TRUE(check_hierarchy(h).empty()) << violations_text(check_hierarchy(h));

  EXPECT_EQ(h.split(1), std::vector<NodeId>{1});
  EXPECT_EQ(h.midpoint(0, 2), m) << "the shared midpoint must be reused";
  EXPECT_EQ(h.num_vertices(), 4u + 5u);
  EXPECT_FALSE(h.is_t_vertex(m));
  EXPECT_TRUE(h.t_vertices().empty());
  EXPECT_EQ(h.num_leaves(), 8u);
  const NodeId across = h.neighbor(child_near_0, on_diagonal);
  ASSERT_NE(across, kNoNode);
  EXPECT_EQ(h.level(across), 1);
  EXPECT_EQ(h.parent(across), 1);
  EXPECT_EQ(h.conforming_mesh().mesh.n_faces(), 8u);
  EXPECT_TRUE(check_hierarchy(h).empty()) << violations_text(check_hierarchy(h));
}

TEST(Hierarchy, SplittingNextToCoarserLeafForcesItFirst) {
  SurfaceHierarchy h(two_triangles());
  h.split(0);
  // The level-1 child of root 0 at vertex 0 has an edge inside root 1's
  // diagonal: splitting it must split root 1 first.
  const NodeId c = leaf_containing(h, {0.2, 0.1, 0.0});
  ASSERT_NE(c, kNoNode);
  EXPECT_EQ(h.split(c), (std::vector<NodeId>{1, c}));
  EXPECT_EQ(h.max_level(), 2);
  const NodeId across = leaf_containing(h, {0.1, 0.2, 0.0});
  ASSERT_NE(across, kNoNode);
  EXPECT_EQ(h.level(across), 1);
  EXPECT_EQ(h.root_face(across), 1);
  EXPECT_TRUE(check_hierarchy(h).empty()) << violations_text(check_hierarchy(h));
}

TEST(Hierarchy, ForcedSplitsRecurseThroughLevels) {
  // Roots i = face (0, i+1, i+2) of the fan; a point near the centre inside
  // root i is eps * (P(i+1) + P(i+2)).
  SurfaceHierarchy h(hexagon_fan());
  auto near_centre = [](int root, double eps) { return eps * (hex_point(root + 1) + hex_point(root % 6 + 2)); };
  EXPECT_EQ(h.split(0), std::vector<NodeId>{0});
  const NodeId c = leaf_containing(h, near_centre(0, 0.05));
  ASSERT_EQ(h.level(c), 1);
  // c's outer edges lie on the edges root 0 shares with roots 1 and 5.
  const auto first = h.split(c);
  ASSERT_EQ(first.size(), 3u);
  EXPECT_EQ(std::set<NodeId>(first.begin(), first.end() - 1), (std::set<NodeId>{1, 5}));
  EXPECT_EQ(first.back(), c);

  const NodeId g = leaf_containing(h, near_centre(0, 0.05));
  const NodeId b1 = leaf_containing(h, near_centre(1, 0.05));
  const NodeId b5 = leaf_containing(h, near_centre(5, 0.05));
  ASSERT_EQ(h.level(g), 2);
  ASSERT_EQ(h.level(b1), 1);
  ASSERT_EQ(h.level(b5), 1);
  // The level-2 leaf g at the centre forces b1 and b5 (level 1), and these in
  // turn force the level-0 roots 2 and 4 beyond them. Root 3 only touches g
  // at the centre vertex and stays a leaf.
  const auto chain = h.split(g);
  ASSERT_EQ(chain.size(), 5u);
  EXPECT_EQ(chain.back(), g);
  EXPECT_EQ(std::set<NodeId>(chain.begin(), chain.end()), (std::set<NodeId>{2, 4, b1, b5, g}));
  auto pos = [&](NodeId n) { return std::find(chain.begin(), chain.end(), n) - chain.begin(); };
  EXPECT_LT(pos(2), pos(b1));
  EXPECT_LT(pos(4), pos(b5));
  EXPECT_TRUE(h.is_leaf(3));
  EXPECT_EQ(h.max_level(), 3);
  EXPECT_TRUE(check_hierarchy(h).empty()) << violations_text(check_hierarchy(h));
}

TEST(Hierarchy, TVerticesCloseLeavesIntoTwoOrThreeTriangles) {
  SurfaceHierarchy h(hexagon_fan());
  h.split(0);
  h.split(2);
  // Root 1 = (0,2,3) borders both split roots (2 T-vertices -> 3 triangles);
  // roots 5 and 3 border one each (-> 2 triangles); root 4 none.
  EXPECT_EQ(h.t_vertices().size(), 4u);
  for (const VertexId m : {h.midpoint(0, 2), h.midpoint(0, 3), h.midpoint(0, 1), h.midpoint(0, 4)}) {
    ASSERT_NE(m, kNoVertex);
    EXPECT_TRUE(h.is_t_vertex(m));
  }
  const ConformingMesh cm = h.conforming_mesh();
  EXPECT_EQ(cm.mesh.n_faces(), 4u + 4u + 3u + 2u + 2u + 1u);
  double area = 0.0;
  std::size_t in_root1 = 0;
  const Vec3 p0(0.0, 0.0, 0.0), p2 = hex_point(2), p3 = hex_point(3);
  for (const auto& f : face_list(cm.mesh)) {
    const Vec3 a = cm.mesh.point(OpenMesh::VertexHandle(f[0]));
    const Vec3 b = cm.mesh.point(OpenMesh::VertexHandle(f[1]));
    const Vec3 c = cm.mesh.point(OpenMesh::VertexHandle(f[2]));
    const double a2 = signed_area2(a, b, c);
    EXPECT_GT(a2, 0.0);
    area += 0.5 * a2;
    const Vec3 centroid = (a + b + c) / 3.0;
    if (signed_area2(p0, p2, centroid) > 0 && signed_area2(p2, p3, centroid) > 0 &&
        signed_area2(p3, p0, centroid) > 0) {
      ++in_root1;
    }
  }
  EXPECT_EQ(in_root1, 3u);
  EXPECT_NEAR(area, 1.5 * std::sqrt(3.0), 1e-12);
  EXPECT_TRUE(check_hierarchy(h).empty()) << violations_text(check_hierarchy(h));
}

TEST(Hierarchy, UnsplitConformingMeshEqualsInput) {
  for (const TriMesh& initial : {grid_mesh(), hexagon_fan(), two_triangles(), single_triangle()}) {
    const SurfaceHierarchy h(initial);
    const ConformingMesh cm = h.conforming_mesh();
    ASSERT_EQ(cm.mesh.n_vertices(), initial.n_vertices());
    ASSERT_EQ(cm.source.size(), initial.n_vertices());
    for (const auto vh : initial.vertices()) {
      EXPECT_EQ(cm.source[vh.idx()], vh.idx());
      EXPECT_EQ(cm.mesh.point(vh), initial.point(vh));
    }
    const auto in_faces = face_list(initial);
    const auto out_faces = face_list(cm.mesh);
    ASSERT_EQ(out_faces.size(), in_faces.size());
    for (std::size_t i = 0; i < in_faces.size(); ++i) {
      EXPECT_TRUE(same_oriented_triangle(out_faces[i], in_faces[i])) << "face " << i;
    }
  }
}

// Random leaf splits on the grid with a fixed seed, levels capped at kCap.
// Calls `batch` after every kBatch requested splits.
constexpr int kCap = 7;
constexpr int kSplits = 3000;
constexpr int kBatch = 100;

void random_splits(SurfaceHierarchy& h, unsigned seed, const std::function<void(int)>& batch) {
  std::mt19937 rng(seed);
  // Candidates with lazy removal: every entry that is no longer a splittable
  // leaf is dropped when drawn, so draws are uniform over splittable leaves.
  std::vector<NodeId> pool = h.leaves();
  for (int s = 1; s <= kSplits; ++s) {
    NodeId n = kNoNode;
    while (n == kNoNode) {
      ASSERT_FALSE(pool.empty());
      std::uniform_int_distribution<std::size_t> pick(0, pool.size() - 1);
      const std::size_t i = pick(rng);
      if (h.is_leaf(pool[i]) && h.level(pool[i]) < kCap) {
        n = pool[i];
      } else {
        pool[i] = pool.back();
        pool.pop_back();
      }
    }
    const auto split = h.split(n);
    ASSERT_FALSE(split.empty());
    ASSERT_EQ(split.back(), n);
    for (const NodeId p : split) {
      for (int c = 0; c < 4; ++c) pool.push_back(h.child(p, c));
    }
    if (s % kBatch == 0) {
      batch(s);
      if (::testing::Test::HasFatalFailure()) return;
    }
  }
}

bool on_grid_boundary(const Vec3& a, const Vec3& b) {
  for (int axis = 0; axis < 2; ++axis) {
    for (const double side : {0.0, double(kGrid)}) {
      if (a[axis] == side && b[axis] == side) return true;
    }
  }
  return false;
}

TEST(Hierarchy, RandomSplitsKeepInvariantsAndExportCrackFree) {
  SurfaceHierarchy h(grid_mesh());
  const std::size_t initial_vertices = h.num_vertices();
  std::array<int, 4> t_cases{};  // leaves seen with 0..3 T-vertices on their edges
  random_splits(h, 20240611u, [&](int step) {
    SCOPED_TRACE("after " + std::to_string(step) + " splits");
    const auto violations = check_hierarchy(h);
    ASSERT_TRUE(violations.empty()) << violations_text(violations);

    // Counts from the structure: each split adds 4 nodes and 3 leaves, and
    // one vertex per distinct edge of a split node.
    std::size_t split_nodes = 0;
    std::set<std::pair<VertexId, VertexId>> split_edges;
    for (NodeId n = 0; n < static_cast<NodeId>(h.num_nodes()); ++n) {
      if (h.is_leaf(n)) continue;
      ++split_nodes;
      const auto& c = h.corners(n);
      for (int k = 0; k < 3; ++k) split_edges.insert(std::minmax(c[k], c[(k + 1) % 3]));
    }
    EXPECT_GE(split_nodes, static_cast<std::size_t>(step));
    EXPECT_EQ(h.num_nodes(), h.num_roots() + 4 * split_nodes);
    EXPECT_EQ(h.num_leaves(), h.num_roots() + 3 * split_nodes);
    EXPECT_EQ(h.num_vertices(), initial_vertices + split_edges.size());
    EXPECT_LE(h.max_level(), kCap);

    const auto leaves = h.leaves();
    std::size_t t_on_leaf_edges = 0;
    for (const NodeId n : leaves) {
      const auto& c = h.corners(n);
      int t = 0;
      for (int k = 0; k < 3; ++k) t += h.midpoint(c[k], c[(k + 1) % 3]) != kNoVertex;
      ++t_cases[t];
      t_on_leaf_edges += t;
    }
    // In a restricted quadtree each T-vertex lies inside exactly one leaf edge.
    EXPECT_EQ(h.t_vertices().size(), t_on_leaf_edges);

    const ConformingMesh cm = h.conforming_mesh();
    const TriMesh& out = cm.mesh;
    // Every vertex is a leaf corner or a T-vertex, so all are exported; each
    // T-vertex adds exactly one triangle to its leaf.
    ASSERT_EQ(out.n_vertices(), h.num_vertices());
    ASSERT_EQ(cm.source.size(), out.n_vertices());
    EXPECT_EQ(out.n_faces(), leaves.size() + h.t_vertices().size());
    for (const auto vh : out.vertices()) {
      ASSERT_EQ(out.point(vh), h.point(cm.source[vh.idx()]));
    }

    // Crack-free: every directed edge occurs once; its reverse occurs too
    // unless it lies on the outer boundary of the grid. Orientation ccw and
    // total area equal to the initial area.
    std::map<std::pair<int, int>, int> directed;
    double area = 0.0;
    for (const auto& f : face_list(out)) {
      const Vec3 a = out.point(OpenMesh::VertexHandle(f[0]));
      const Vec3 b = out.point(OpenMesh::VertexHandle(f[1]));
      const Vec3 c = out.point(OpenMesh::VertexHandle(f[2]));
      const double a2 = signed_area2(a, b, c);
      EXPECT_GT(a2, 0.0);
      area += 0.5 * a2;
      for (int k = 0; k < 3; ++k) ++directed[{f[k], f[(k + 1) % 3]}];
    }
    EXPECT_NEAR(area, double(kGrid * kGrid), 1e-12 * kGrid * kGrid);
    std::size_t boundary_edges = 0;
    for (const auto& [e, count] : directed) {
      ASSERT_EQ(count, 1) << "directed edge repeated";
      if (directed.count({e.second, e.first}) == 0) {
        ++boundary_edges;
        ASSERT_TRUE(on_grid_boundary(out.point(OpenMesh::VertexHandle(e.first)),
                                     out.point(OpenMesh::VertexHandle(e.second))))
            << "open edge (" << e.first << "," << e.second << ") inside the surface: a crack";
      }
    }
    // A disk: V - E + F = 1, with E counted once per undirected edge.
    const std::size_t undirected = (directed.size() + boundary_edges) / 2;
    EXPECT_EQ(static_cast<long>(out.n_vertices()) - static_cast<long>(undirected) + static_cast<long>(out.n_faces()),
              1);
  });
  // The random run must have exercised every way of closing a leaf.
  for (int t = 0; t < 4; ++t) EXPECT_GT(t_cases[t], 0) << t << " T-vertices on a leaf never occurred";
  EXPECT_EQ(h.max_level(), kCap);
}

TEST(Hierarchy, RandomSplitsExportPassesConformingCheck) {
  SurfaceHierarchy h(grid_mesh());
  random_splits(h, 20240611u, [&](int step) {
    const auto violations = check_conforming_mesh(test::raw_mesh(h.conforming_mesh().mesh));
    ASSERT_TRUE(violations.empty()) << "after " << step << " splits:\n" << violations_text(violations);
  });
}

TEST(Hierarchy, ExportedFacesTileTheirLeaves) {
  // Each exported face names the leaf it lies in: the faces of one leaf
  // cover exactly its area, and every face's centroid is inside that leaf.
  SurfaceHierarchy h(grid_mesh());
  random_splits(h, 11, [](int) {});
  const ConformingMesh out = h.conforming_mesh();
  ASSERT_EQ(out.leaf.size(), out.mesh.n_faces());
  std::map<NodeId, double> covered;
  for (const auto fh : out.mesh.faces()) {
    const NodeId leaf = out.leaf[fh.idx()];
    ASSERT_TRUE(h.is_leaf(leaf));
    covered[leaf] += out.mesh.calc_face_area(fh);
    if (fh.idx() % 97 == 0) {
      EXPECT_EQ(leaf_containing(h, out.mesh.calc_face_centroid(fh)), leaf);
    }
  }
  EXPECT_EQ(covered.size(), h.num_leaves());
  for (const auto& [leaf, area] : covered) {
    const auto& v = h.corners(leaf);
    const double leaf_area = 0.5 * std::abs(signed_area2(h.point(v[0]), h.point(v[1]), h.point(v[2])));
    EXPECT_NEAR(area, leaf_area, 1e-12 * leaf_area);
  }
}

// MeshedScene::area reads a node's area as its root's over 4^level: a split
// cuts a triangle into four congruent ones on the root's plane, on a curved
// surface's flat facets as on a plane. Checked against each node's corners
// after random splits of a tessellated sphere and a cube.
TEST(Hierarchy, ANodesAreaIsItsRootsOverFourPerLevel) {
  for (const Scene& scene : {test::furnace_sphere(), test::furnace_cube(0.5, 1.0)}) {
    MeshingOptions meshing;
    meshing.max_edge = 0.5;
    MeshedScene model(scene, meshing);
    std::mt19937 random(5);
    std::size_t checked = 0;
    for (int s = 0; s < model.num_surfaces(); ++s) {
      SurfaceHierarchy& h = model.hierarchy(s);
      for (int round = 0; round < 40; ++round) {
        const std::vector<NodeId> leaves = h.leaves();
        h.split(leaves[std::uniform_int_distribution<std::size_t>(0, leaves.size() - 1)(random)]);
      }
      for (std::size_t n = 0; n < h.num_nodes(); ++n) {
        const auto t = model.triangle(s, static_cast<NodeId>(n));
        const double corners = 0.5 * OpenMesh::cross(t[1] - t[0], t[2] - t[0]).norm();
        EXPECT_NEAR(model.area(s, static_cast<NodeId>(n)), corners, 1e-12 * corners)
            << scene.surfaces[s].name << " node " << n << " level " << h.level(static_cast<NodeId>(n));
        ++checked;
      }
    }
    EXPECT_GT(checked, 400u) << scene.surfaces.front().name;
  }
}

TEST(Hierarchy, SameSeedSameHierarchy) {
  SurfaceHierarchy a(grid_mesh());
  SurfaceHierarchy b(grid_mesh());
  random_splits(a, 7u, [](int) {});
  random_splits(b, 7u, [](int) {});
  ASSERT_EQ(a.num_nodes(), b.num_nodes());
  ASSERT_EQ(a.num_vertices(), b.num_vertices());
  for (NodeId n = 0; n < static_cast<NodeId>(a.num_nodes()); ++n) {
    ASSERT_EQ(a.corners(n), b.corners(n));
    ASSERT_EQ(a.is_leaf(n), b.is_leaf(n));
  }
  for (VertexId v = 0; v < static_cast<VertexId>(a.num_vertices()); ++v) {
    ASSERT_EQ(a.point(v), b.point(v));
  }
  SurfaceHierarchy c(grid_mesh());
  random_splits(c, 8u, [](int) {});
  const bool identical = c.num_nodes() == a.num_nodes() && c.leaves() == a.leaves();
  EXPECT_FALSE(identical) << "another seed should give another hierarchy";
}

TEST(CornerValues, GrowsAndIndexesByNodeAndCorner) {
  CornerValues<double> values;
  values.at(4, 2) = 3.5;
  EXPECT_EQ(values.size_nodes(), 5u);
  EXPECT_TRUE(values.has(4));
  EXPECT_FALSE(values.has(5));
  EXPECT_EQ(values.at(4, 1), 0.0);
  const auto& cv = values;
  EXPECT_EQ(cv.at(4, 2), 3.5);
  EXPECT_THROW(cv.at(5, 0), std::out_of_range);
}

}  // namespace
}  // namespace lhr
