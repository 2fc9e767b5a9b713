#include "mesh/cgal_meshing.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <stdexcept>
#include <string>

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Delaunay_mesh_face_base_2.h>
#include <CGAL/Delaunay_mesh_size_criteria_2.h>
#include <CGAL/Delaunay_mesher_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_vertex_base_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>
#include <CGAL/boost/graph/graph_traits_TriMesh_ArrayKernelT.h>
#include <CGAL/boost/graph/properties_TriMesh_ArrayKernelT.h>
#include <CGAL/Polygon_mesh_processing/detect_features.h>
#include <CGAL/Polygon_mesh_processing/remesh.h>

#include "mesh/coarsen.hpp"

namespace lhr {

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;

// Input point a triangulation vertex was created from; -1 for Steiner points.
struct InputVertex {
  int index = -1;
};

using VertexBase =
    CGAL::Triangulation_vertex_base_with_info_2<InputVertex, Kernel, CGAL::Triangulation_vertex_base_2<Kernel>>;
using FaceBase = CGAL::Delaunay_mesh_face_base_2<Kernel>;
using Tds = CGAL::Triangulation_data_structure_2<VertexBase, FaceBase>;
// Contact lines may cross each other (two boxes pushed into each other), so
// CGAL constructs intersection points; crossing polygon edges, which mean
// broken input, are caught by counting vertices (refine_region).
using Cdt = CGAL::Constrained_Delaunay_triangulation_2<Kernel, Tds, CGAL::Exact_predicates_tag>;
using Criteria = CGAL::Delaunay_mesh_size_criteria_2<Cdt>;

constexpr double kPi = 3.14159265358979323846;
// Guard against runaway refinement (and memory) on one surface.
constexpr std::size_t kMaxVerticesPerSurface = std::size_t{1} << 24;
// Curved surfaces: CGAL splits edges longer than 4/3 of the target length,
// so a target of 3/4 h keeps remeshed edges at h (Botsch & Kobbelt 2004).
constexpr double kCurvedTargetFraction = 0.75;
// An input edge where the surface bends by more than this (the angle between
// its two faces' normals) stays a line of the initial mesh, so every
// triangle lies in one input polygon's plane there: the path tracer and the
// vertex reference see the input polygons, and a triangle remeshed across a
// bend of δ tilts by up to δ/2 from them, which changes the cosine toward a
// light at incidence θ by about tan θ · δ/2 (2 % at 45° for δ = 2°) and
// moves a light's horizon to another place on the surface. A 32 × 16 UV
// sphere bends 11.25° at every edge; the published Cornell box's warped
// wall 0.33° and a finely tessellated terrain under 1°, and those are still
// coarsened to the minimum density (docs/design.md §4, "Initial meshing").
constexpr double kKeptBendDeg = 2.0;
constexpr unsigned kRemeshIterations = 3;
// CGAL's remeshing collapses short edges shortest first, taken from a
// search tree of every short edge. On a finely divided curved surface their
// lengths differ a little from place to place, so each collapse walks down
// that tree and into a far part of the mesh, a chain of cache misses that
// lengthens as the input outgrows the caches (10 µs a collapse at 10⁵
// triangles, 23 µs at 10⁶, even toward twice the input's edge length); and
// a collapse toward a target far above the input's edges gathers
// a ring of many vertices and walks it at every later collapse. So a
// surface whose fine edges are under a quarter of the target is first
// coarsened by mesh/coarsen.hpp, in the mesh's own order, toward targets
// halved from the final one down to this many fine edges; each sweep costs
// a bounded amount per triangle, the sizes fall geometrically, and CGAL is
// handed a mesh a few times finer than its target (docs/design.md §4,
// "Curved surfaces").
constexpr double kFinestPassInFineEdges = 2.0;
// The edges that decide whether a surface is fine: the shortest tenth, so a
// finely divided patch on an otherwise coarse surface is coarsened too.
constexpr double kFineEdgeQuantile = 0.1;
// A border or bend vertex whose two constrained edges turn by more
// than this stays fixed, so coarsening the line does not cut its corners.
constexpr double kConstraintCornerDeg = 30.0;

Kernel::Point_2 to_cgal(const Point2& p) { return Kernel::Point_2(p.x, p.y); }
Point2 to_plain(const Kernel::Point_2& p) { return Point2{p.x(), p.y()}; }

double orient2(const Kernel::Point_2& a, const Kernel::Point_2& b, const Kernel::Point_2& c) {
  return lhr::orient2(to_plain(a), to_plain(b), to_plain(c));
}

// Faces connected without crossing a constraint are all inside the region
// or all outside it, so each such component is decided as a whole: outside
// if it reaches the unbounded face, else by the area of its faces whose
// centroids fall inside an input triangle. A per-face test would misjudge the
// slivers that rounding leaves along nearly collinear boundary vertices, and
// the mesher, trusting the marks, would then insert circumcentres of such an
// outside sliver ever farther away without end.
void mark_domain(Cdt& cdt, const PointLocator& input) {
  std::map<Cdt::Face_handle, int> component;
  std::vector<double> inside_area, outside_area;
  std::vector<bool> unbounded;
  for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f) {
    if (component.count(f)) continue;
    const int id = static_cast<int>(inside_area.size());
    inside_area.push_back(0.0);
    outside_area.push_back(0.0);
    unbounded.push_back(false);
    std::vector<Cdt::Face_handle> stack{f};
    component[f] = id;
    while (!stack.empty()) {
      const Cdt::Face_handle g = stack.back();
      stack.pop_back();
      const Kernel::Point_2& a = g->vertex(0)->point();
      const Kernel::Point_2& b = g->vertex(1)->point();
      const Kernel::Point_2& c = g->vertex(2)->point();
      const double area = 0.5 * orient2(a, b, c);
      (input.locate(to_plain(CGAL::centroid(a, b, c))).min_barycentric >= 0.0 ? inside_area : outside_area)[id] += area;
      for (int k = 0; k < 3; ++k) {
        const Cdt::Face_handle n = g->neighbor(k);
        if (cdt.is_constrained(Cdt::Edge(g, k))) continue;
        if (cdt.is_infinite(n)) {
          unbounded[id] = true;
          continue;
        }
        if (component.count(n)) continue;
        component[n] = id;
        stack.push_back(n);
      }
    }
  }
  for (auto& [f, id] : component) f->set_in_domain(!unbounded[id] && inside_area[id] > outside_area[id]);
}

// CGAL's refine_Delaunay_mesh_2, one point at a time, so that a run that
// leaves the region (which Delaunay refinement never does in exact
// arithmetic, but rounding on degenerate input might) ends with an error
// instead of running forever.
void refine(Cdt& cdt, const Criteria& criteria) {
  double x0 = std::numeric_limits<double>::infinity(), y0 = x0, x1 = -x0, y1 = -x0;
  for (auto v = cdt.finite_vertices_begin(); v != cdt.finite_vertices_end(); ++v) {
    x0 = std::min(x0, v->point().x());
    y0 = std::min(y0, v->point().y());
    x1 = std::max(x1, v->point().x());
    y1 = std::max(y1, v->point().y());
  }
  const double pad = 1e-6 * std::hypot(x1 - x0, y1 - y0);
  CGAL::Delaunay_mesher_2<Cdt, Criteria> mesher(cdt, criteria);
  mesher.init(true);
  std::size_t checked = cdt.number_of_vertices();
  while (!mesher.is_refinement_done()) {
    mesher.step_by_step_refine_mesh();
    if (cdt.number_of_vertices() < 2 * checked) continue;
    checked = cdt.number_of_vertices();
    if (checked > kMaxVerticesPerSurface) {
      throw std::runtime_error("needs more than " + std::to_string(kMaxVerticesPerSurface) +
                               " vertices; use a larger --max-edge");
    }
    for (auto v = cdt.finite_vertices_begin(); v != cdt.finite_vertices_end(); ++v) {
      const Kernel::Point_2& p = v->point();
      if (!(p.x() >= x0 - pad && p.x() <= x1 + pad && p.y() >= y0 - pad && p.y() <= y1 + pad)) {
        throw std::runtime_error("Delaunay refinement left the surface (degenerate or overlapping polygons?)");
      }
    }
  }
}

// Only constraint ends are inserted: an input vertex inside a flat part
// carries no shape, and keeping it would force the mesh finer than h
// (docs/design.md §4: minimum density). Points added for contact lines keep
// index -1, so their 3D position comes from the input triangles.
void insert_constraints(Cdt& cdt, const ConstrainedRegion& constraints) {
  const std::vector<Point2>& all_points = constraints.points;
  std::vector<Cdt::Vertex_handle> handles(all_points.size());
  std::vector<bool> used(all_points.size(), false);
  for (const auto& [a, b] : constraints.polygon_edges) used[a] = used[b] = true;
  for (const auto& [a, b] : constraints.contact_edges) used[a] = used[b] = true;
  for (std::size_t i = 0; i < all_points.size(); ++i) {
    if (!used[i]) continue;
    handles[i] = cdt.insert(to_cgal(all_points[i]));
    if (handles[i]->info().index < 0 && i < constraints.num_surface_points) {
      handles[i]->info().index = static_cast<int>(i);
    }
  }
  const std::size_t inserted = cdt.number_of_vertices();
  for (const auto& [a, b] : constraints.polygon_edges) {
    if (handles[a] != handles[b]) cdt.insert_constraint(handles[a], handles[b]);
  }
  // Constraints crossing each other get a vertex at the crossing.
  if (cdt.number_of_vertices() != inserted) throw std::runtime_error("polygon edges cross each other");
  for (const auto& [a, b] : constraints.contact_edges) {
    if (handles[a] != handles[b]) cdt.insert_constraint(handles[a], handles[b]);
  }
}

// The faces in the region, their vertices in triangulation order
// (deterministic), not in map order.
RegionMesh region_faces(const Cdt& cdt) {
  RegionMesh out;
  std::map<Cdt::Vertex_handle, int> index;
  for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f) {
    if (!f->is_in_domain()) continue;
    for (int k = 0; k < 3; ++k) index.emplace(f->vertex(k), -1);
  }
  for (auto vit = cdt.finite_vertices_begin(); vit != cdt.finite_vertices_end(); ++vit) {
    const auto it = index.find(vit);
    if (it == index.end()) continue;
    it->second = static_cast<int>(out.points.size());
    out.points.push_back(to_plain(vit->point()));
    out.surface_point.push_back(vit->info().index);
  }
  for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f) {
    if (!f->is_in_domain()) continue;
    out.triangles.push_back({index.at(f->vertex(0)), index.at(f->vertex(1)), index.at(f->vertex(2))});
  }
  return out;
}

// Reads and writes OpenMesh points as CGAL points in double precision; the
// adapter's own map rounds written points to float.
struct PointMap {
  using key_type = boost::graph_traits<TriMesh>::vertex_descriptor;
  using value_type = Kernel::Point_3;
  using reference = Kernel::Point_3;
  using category = boost::read_write_property_map_tag;
  TriMesh* mesh = nullptr;
  MeshingCheckpoint* checkpoint = nullptr;

  friend value_type get(const PointMap& m, key_type v) {
    if (m.checkpoint != nullptr) m.checkpoint->tick();
    const Vec3& p = m.mesh->point(v);
    return value_type(p[0], p[1], p[2]);
  }
  friend void put(const PointMap& m, key_type v, const value_type& p) {
    m.mesh->set_point(v, Vec3(p.x(), p.y(), p.z()));
  }
};

// Constrained-or-not flags on OpenMesh properties, so they follow the mesh
// through splits; CGAL's dynamic bool maps do not compile against OpenMesh's
// std::vector<bool> storage.
OpenMesh::EdgeHandle flag_handle(const TriMesh& mesh, boost::graph_traits<TriMesh>::edge_descriptor e) {
  return mesh.edge_handle(e.halfedge());
}
TriMesh::VertexHandle flag_handle(const TriMesh&, TriMesh::VertexHandle v) { return v; }

template <typename Key, typename Property>
struct FlagMap {
  using key_type = Key;
  using value_type = bool;
  using reference = bool;
  using category = boost::read_write_property_map_tag;
  TriMesh* mesh = nullptr;
  Property prop;

  friend bool get(const FlagMap& m, key_type k) { return m.mesh->property(m.prop, flag_handle(*m.mesh, k)) != 0; }
  friend void put(const FlagMap& m, key_type k, bool value) {
    m.mesh->property(m.prop, flag_handle(*m.mesh, k)) = value ? 1 : 0;
  }
};
using EdgeFlagMap = FlagMap<boost::graph_traits<TriMesh>::edge_descriptor, OpenMesh::EPropHandleT<unsigned char>>;
using VertexFlagMap = FlagMap<boost::graph_traits<TriMesh>::vertex_descriptor, OpenMesh::VPropHandleT<unsigned char>>;

double edge_length(const TriMesh& mesh, boost::graph_traits<TriMesh>::edge_descriptor e) {
  return mesh.calc_edge_length(mesh.edge_handle(e.halfedge()));
}

// The targets of the coarsening passes, smallest first: the final target
// halved while the half is still kFinestPassInFineEdges fine edges long.
std::vector<double> coarsening_targets(const TriMesh& mesh, double target) {
  std::vector<double> lengths;
  lengths.reserve(mesh.n_edges());
  for (const auto e : mesh.edges()) lengths.push_back(mesh.calc_edge_length(e));
  if (lengths.empty()) return {};
  const auto fine = lengths.begin() + static_cast<std::ptrdiff_t>(kFineEdgeQuantile * (lengths.size() - 1));
  std::nth_element(lengths.begin(), fine, lengths.end());
  std::vector<double> targets;
  for (double t = 0.5 * target; *fine > 0.0 && t >= kFinestPassInFineEdges * *fine; t *= 0.5) targets.push_back(t);
  std::reverse(targets.begin(), targets.end());
  return targets;
}

}  // namespace

// Splits one polygon (counter-clockwise in the plane) into triangles: a fan
// when every fan triangle is counter-clockwise (then the fan tiles the
// polygon: its wedges around vertex 0 are disjoint), else ear clipping.
// Degenerate (collinear) pieces are dropped.
void triangulate_polygon(const std::vector<int>& poly, const std::vector<Point2>& points, std::size_t polygon_index,
                         std::vector<std::array<int, 3>>& out) {
  const auto q = [&](int i) { return to_cgal(points[i]); };
  bool fan_ok = true;
  for (std::size_t i = 1; i + 1 < poly.size() && fan_ok; ++i) {
    fan_ok = CGAL::orientation(q(poly[0]), q(poly[i]), q(poly[i + 1])) != CGAL::RIGHT_TURN;
  }
  if (fan_ok) {
    for (std::size_t i = 1; i + 1 < poly.size(); ++i) {
      if (CGAL::orientation(q(poly[0]), q(poly[i]), q(poly[i + 1])) == CGAL::LEFT_TURN) {
        out.push_back({poly[0], poly[i], poly[i + 1]});
      }
    }
    return;
  }
  std::vector<int> ring = poly;
  while (ring.size() >= 3) {
    const std::size_t n = ring.size();
    bool clipped = false;
    for (std::size_t i = 0; i < n && !clipped; ++i) {
      const int a = ring[(i + n - 1) % n], b = ring[i], c = ring[(i + 1) % n];
      if (CGAL::orientation(q(a), q(b), q(c)) != CGAL::LEFT_TURN) continue;
      bool empty = true;
      for (std::size_t j = 0; j < n && empty; ++j) {
        const int r = ring[j];
        if (r == a || r == b || r == c || points[r] == points[a] || points[r] == points[b] || points[r] == points[c]) {
          continue;
        }
        empty = !(CGAL::orientation(q(a), q(b), q(r)) != CGAL::RIGHT_TURN &&
                  CGAL::orientation(q(b), q(c), q(r)) != CGAL::RIGHT_TURN &&
                  CGAL::orientation(q(c), q(a), q(r)) != CGAL::RIGHT_TURN);
      }
      if (empty) {
        out.push_back({a, b, c});
        ring.erase(ring.begin() + static_cast<std::ptrdiff_t>(i));
        clipped = true;
      }
    }
    if (clipped) continue;
    for (std::size_t i = 0; i < n && !clipped; ++i) {
      const int a = ring[(i + n - 1) % n], b = ring[i], c = ring[(i + 1) % n];
      if (CGAL::orientation(q(a), q(b), q(c)) == CGAL::COLLINEAR) {
        ring.erase(ring.begin() + static_cast<std::ptrdiff_t>(i));
        clipped = true;
      }
    }
    if (!clipped) {
      throw std::runtime_error("polygon " + std::to_string(polygon_index) +
                               " is self-intersecting or not counter-clockwise seen from the surface front");
    }
  }
}

RegionMesh refine_region(const ConstrainedRegion& constraints, const PointLocator& region, double shape_bound,
                         double size_bound) {
  Cdt cdt;
  insert_constraints(cdt, constraints);
  // Polygons that exactly cover each other (a duplicated face) leave no
  // boundary edge, so nothing was inserted; CGAL's mesher needs a 2D
  // triangulation and follows null neighbours otherwise.
  if (cdt.dimension() < 2) throw std::runtime_error("has no boundary edge (duplicated or overlapping polygons?)");
  mark_domain(cdt, region);
  refine(cdt, Criteria(shape_bound, size_bound));
  return region_faces(cdt);
}

std::vector<RemeshPass> remesh_isotropic(TriMesh& mesh, double h, const std::vector<TriMesh::VertexHandle>& fixed,
                                         MeshingCheckpoint& checkpoint) {
  namespace PMP = CGAL::Polygon_mesh_processing;
  mesh.request_vertex_status();
  mesh.request_edge_status();
  mesh.request_halfedge_status();
  mesh.request_face_status();

  const PointMap points{&mesh, &checkpoint};
  EdgeFlagMap constrained_edge;
  constrained_edge.mesh = &mesh;
  VertexFlagMap constrained_vertex;
  constrained_vertex.mesh = &mesh;
  mesh.add_property(constrained_edge.prop);
  mesh.add_property(constrained_vertex.prop);
  for (const auto e : edges(mesh)) put(constrained_edge, e, CGAL::is_border(e, mesh));
  PMP::detect_sharp_edges(mesh, kKeptBendDeg, constrained_edge, CGAL::parameters::vertex_point_map(points));
  for (const auto v : vertices(mesh)) put(constrained_vertex, v, false);
  for (const auto v : fixed) put(constrained_vertex, v, true);
  // Constrained edges are split and collapsed along themselves, so the
  // border and the bends keep their polyline; vertices where such
  // lines meet or turn are kept where they are.
  for (const auto v : mesh.vertices()) {
    std::vector<Vec3> directions;
    for (const auto he : mesh.voh_range(v)) {
      if (get(constrained_edge, edge(he, mesh))) directions.push_back(mesh.calc_edge_vector(he).normalized());
    }
    if (directions.empty()) continue;
    if (directions.size() != 2 ||
        OpenMesh::dot(directions[0], -directions[1]) < std::cos(kConstraintCornerDeg * kPi / 180.0)) {
      put(constrained_vertex, v, true);
    }
  }

  const double target_length = kCurvedTargetFraction * h;
  std::vector<RemeshPass> passes;
  const CoarseningConstraints constraints{constrained_edge.prop, constrained_vertex.prop};
  for (const double t : coarsening_targets(mesh, target_length)) {
    passes.push_back({t, mesh.n_faces()});
    collapse_short_edges(mesh, t, constraints, checkpoint);
    mesh.garbage_collection();
  }
  checkpoint();
  passes.push_back({target_length, mesh.n_faces()});
  PMP::isotropic_remeshing(faces(mesh), target_length, mesh,
                           CGAL::parameters::number_of_iterations(kRemeshIterations)
                               .edge_is_constrained_map(constrained_edge)
                               .vertex_is_constrained_map(constrained_vertex)
                               .protect_constraints(false)
                               .vertex_point_map(points));

  // Smoothing can stretch an edge past h; split what remains.
  std::vector<boost::graph_traits<TriMesh>::edge_descriptor> to_split;
  for (int round = 0; round < 8; ++round) {
    to_split.clear();
    for (const auto e : edges(mesh)) {
      if (edge_length(mesh, e) > h) to_split.push_back(e);
    }
    if (to_split.empty()) break;
    checkpoint();
    PMP::split_long_edges(to_split, h * (1.0 - 1e-12), mesh,
                          CGAL::parameters::edge_is_constrained_map(constrained_edge).vertex_point_map(points));
  }
  mesh.remove_property(constrained_edge.prop);
  mesh.remove_property(constrained_vertex.prop);
  return passes;
}

}  // namespace lhr
