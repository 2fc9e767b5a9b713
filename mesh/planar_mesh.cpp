#include "mesh/planar_mesh.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <stdexcept>
#include <string>
#include <utility>

#include "mesh/cgal_meshing.hpp"
#include "mesh/contact_constraints.hpp"
#include "mesh/edge_key.hpp"
#include "mesh/point2.hpp"
#include "mesh/point_locator.hpp"

namespace lhr {

namespace {

constexpr double kPi = 3.14159265358979323846;
// Largest smallest-angle bound for which Delaunay refinement provably
// terminates: shape bound B = sin^2(angle) = 0.125 (CGAL Delaunay_mesh_criteria_2).
const double kMaxMinAngleRad = std::asin(std::sqrt(0.125));
// Adjacent input triangles whose normals differ by more than this are kept
// apart by a constraint so the output follows the input's piecewise-linear
// shape; below it the bend changes areas by ~angle^2, far under rounding.
constexpr double kCreaseAngleRad = 1e-9;
// Input triangles thinner than this (smallest angle in radians, about) are
// taken as degenerate.
constexpr double kDegenerateSine = 1e-10;

// Area-weighted normal (Newell), used when the surface carries none.
Vec3 newell_vector_area(const Surface& surface) {
  Vec3 sum(0, 0, 0);
  for (const auto& poly : surface.polygons) {
    const Vec3& o = surface.points[poly[0]];
    for (std::size_t i = 1; i + 1 < poly.size(); ++i) {
      sum += 0.5 * OpenMesh::cross(surface.points[poly[i]] - o, surface.points[poly[i + 1]] - o);
    }
  }
  return sum;
}

// The surface's plane frame (u, v, n), right-handed, so counter-clockwise in
// (u, v) is counter-clockwise seen from the front.
struct PlaneFrame {
  Vec3 origin, u, v, n;
  Point2 project(const Vec3& p) const {
    const Vec3 d = p - origin;
    return Point2{OpenMesh::dot(d, u), OpenMesh::dot(d, v)};
  }
};

PlaneFrame plane_frame(const Surface& surface) {
  const Vec3 vector_area = newell_vector_area(surface);
  Vec3 n = surface.normal;
  if (!(n.norm() > 0.5 && n.norm() < 1.5)) n = vector_area;
  if (!(n.norm() > 0.0)) throw std::runtime_error("polygons have zero area");
  n.normalize();
  if (OpenMesh::dot(vector_area, n) <= 0.0) {
    throw std::runtime_error("polygons face away from the surface normal");
  }
  int axis = 0;
  for (int k = 1; k < 3; ++k) {
    if (std::abs(n[k]) < std::abs(n[axis])) axis = k;
  }
  Vec3 e(0, 0, 0);
  e[axis] = 1.0;
  const Vec3 u = OpenMesh::cross(n, e).normalized();
  return PlaneFrame{surface.points[surface.polygons[0][0]], u, OpenMesh::cross(n, u), n};
}

// The polygons split into triangles, in polygon order, and the area of all
// the pieces, slivers included (the area the mesh must cover).
struct InputTriangles {
  std::vector<std::array<int, 3>> triangles;
  double area = 0.0;
};

InputTriangles input_triangles(const Surface& surface, const std::vector<Point2>& q, MeshingCheckpoint& checkpoint) {
  InputTriangles input;
  for (std::size_t p = 0; p < surface.polygons.size(); ++p) {
    checkpoint.tick();
    const auto& poly = surface.polygons[p];
    double signed_area = 0.0;
    for (std::size_t i = 0; i < poly.size(); ++i) {
      const Point2& a = q[poly[i]];
      const Point2& b = q[poly[(i + 1) % poly.size()]];
      signed_area += a.x * b.y - a.y * b.x;
    }
    if (!(signed_area > 0.0)) {
      throw std::runtime_error("polygon " + std::to_string(p) +
                               " is degenerate or not counter-clockwise seen from the surface front");
    }
    const std::size_t first = input.triangles.size();
    triangulate_polygon(poly, q, p, input.triangles);
    for (std::size_t t = first; t < input.triangles.size(); ++t) {
      const auto& tri = input.triangles[t];
      input.area += 0.5 * orient2(q[tri[0]], q[tri[1]], q[tri[2]]);
    }
  }
  // Pieces cut off between collinear polygon vertices are slivers whose
  // normals are rounding noise; they carry no area or shape, so neither the
  // tilt, the crease test nor the point lookup may use them.
  std::erase_if(input.triangles, [&](const std::array<int, 3>& t) {
    const Point2 &a = q[t[0]], &b = q[t[1]], &c = q[t[2]];
    const double longest = std::max({squared_distance(a, b), squared_distance(b, c), squared_distance(c, a)});
    return !(orient2(a, b, c) > kDegenerateSine * longest);
  });
  if (input.triangles.empty()) throw std::runtime_error("polygons have zero area");
  return input;
}

// Unit normal of each input triangle, and the smallest cosine of their tilt
// against the frame: a 2D length l is at most l / cos(tilt) in 3D, and
// angles change by at most 1/cos(tilt) - 1 radians (the 3D triangle projects
// onto the 2D one).
double min_cos_tilt(const Surface& surface, const std::vector<std::array<int, 3>>& triangles, const Vec3& n,
                    std::vector<Vec3>& tri_normal, MeshingCheckpoint& checkpoint) {
  tri_normal.resize(triangles.size());
  double min_cos = 1.0;
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    checkpoint.tick();
    const auto& tri = triangles[t];
    const Vec3& a = surface.points[tri[0]];
    const Vec3 c = OpenMesh::cross(surface.points[tri[1]] - a, surface.points[tri[2]] - a);
    tri_normal[t] = c.normalized();
    const double cos_tilt = OpenMesh::dot(tri_normal[t], n);
    if (!(cos_tilt > 0.5)) {
      throw std::runtime_error("is marked planar but bends by more than 60 degrees; mesh it as a curved surface");
    }
    min_cos = std::min(min_cos, cos_tilt);
  }
  return min_cos;
}

// Constraints: boundary edges (used by exactly one polygon) and creases of
// the piecewise-linear input inside the region.
std::vector<std::pair<int, int>> polygon_constraints(const Surface& surface,
                                                     const std::vector<std::array<int, 3>>& triangles,
                                                     const std::vector<Vec3>& tri_normal,
                                                     MeshingCheckpoint& checkpoint) {
  std::map<std::uint64_t, int> polygon_edge_uses;
  for (const auto& poly : surface.polygons) {
    checkpoint.tick();
    for (std::size_t i = 0; i < poly.size(); ++i) {
      if (poly[i] != poly[(i + 1) % poly.size()]) ++polygon_edge_uses[edge_key(poly[i], poly[(i + 1) % poly.size()])];
    }
  }
  std::vector<std::pair<int, int>> constraints;
  for (const auto& [key, uses] : polygon_edge_uses) {
    checkpoint.tick();
    if (uses > 2) {
      throw std::runtime_error("edge (" + std::to_string(key >> 32) + "," + std::to_string(key & 0xffffffffu) +
                               ") is shared by " + std::to_string(uses) + " polygons");
    }
    if (uses == 1) constraints.push_back(edge_of(key));
  }
  std::map<std::uint64_t, std::vector<int>> triangle_edges;
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    checkpoint.tick();
    for (int k = 0; k < 3; ++k) {
      triangle_edges[edge_key(triangles[t][k], triangles[t][(k + 1) % 3])].push_back(static_cast<int>(t));
    }
  }
  for (const auto& [key, tris] : triangle_edges) {
    checkpoint.tick();
    if (tris.size() != 2 || (polygon_edge_uses.count(key) && polygon_edge_uses.at(key) == 1)) continue;
    const double c = std::clamp(OpenMesh::dot(tri_normal[tris[0]], tri_normal[tris[1]]), -1.0, 1.0);
    const double s = OpenMesh::cross(tri_normal[tris[0]], tri_normal[tris[1]]).norm();
    if (std::atan2(s, c) > kCreaseAngleRad) constraints.push_back(edge_of(key));
  }
  return constraints;
}

// The polygons' constraints with the contact lines added (contact_constraints.hpp).
ConstrainedRegion region_constraints(const PlaneFrame& frame, const std::vector<Point2>& q,
                                     const std::vector<std::array<int, 3>>& triangles,
                                     const std::vector<std::pair<int, int>>& polygon_edges,
                                     const std::vector<Segment3>& contacts, double contact_tolerance) {
  std::vector<std::pair<Point2, Point2>> contacts2;
  for (const Segment3& c : contacts) contacts2.emplace_back(frame.project(c[0]), frame.project(c[1]));
  ContactConstraints plan = plan_contacts(q, triangles, polygon_edges, contacts2, contact_tolerance);
  ConstrainedRegion region;
  region.points = q;
  region.points.insert(region.points.end(), plan.points.begin(), plan.points.end());
  region.num_surface_points = q.size();
  region.polygon_edges = std::move(plan.polygon_edges);
  region.contact_edges = std::move(plan.contact_edges);
  return region;
}

// The 2D mesh in 3D: input points where they were, the others on the input
// triangle they fall in. Checks that the mesh covers the polygons' area.
TriMesh lift(const Surface& surface, const RegionMesh& mesh2, const PointLocator& input, double input_area2,
             MeshingCheckpoint& checkpoint) {
  TriMesh mesh;
  std::vector<TriMesh::VertexHandle> handles;
  handles.reserve(mesh2.points.size());
  for (std::size_t i = 0; i < mesh2.points.size(); ++i) {
    checkpoint.tick();
    Vec3 p;
    if (mesh2.surface_point[i] >= 0) {
      p = surface.points[mesh2.surface_point[i]];
    } else {
      const PointLocator::Location loc = input.locate(mesh2.points[i]);
      if (loc.triangle < 0 || loc.min_barycentric < -1e-6) {
        throw std::runtime_error("mesher placed a point outside the surface (overlapping polygons?)");
      }
      std::array<double, 3> w = loc.barycentric;
      double sum = 0.0;
      for (double& x : w) sum += (x = std::max(x, 0.0));
      const auto& tri = input.triangles()[loc.triangle];
      p = (w[0] / sum) * surface.points[tri[0]] + (w[1] / sum) * surface.points[tri[1]] +
          (w[2] / sum) * surface.points[tri[2]];
    }
    handles.push_back(mesh.add_vertex(p));
  }
  double output_area2 = 0.0;
  for (const auto& t : mesh2.triangles) {
    checkpoint.tick();
    output_area2 += 0.5 * orient2(mesh2.points[t[0]], mesh2.points[t[1]], mesh2.points[t[2]]);
    const auto fh = mesh.add_face(handles[t[0]], handles[t[1]], handles[t[2]]);
    if (!fh.is_valid()) {
      throw std::runtime_error("the surface's region is not manifold (it touches itself at a vertex)");
    }
  }
  if (mesh.n_faces() == 0) throw std::runtime_error("meshing produced no triangles");
  if (std::abs(output_area2 - input_area2) > 1e-9 * input_area2) {
    throw std::runtime_error("polygons overlap or leave gaps (meshed area " + std::to_string(output_area2) +
                             " vs polygon area " + std::to_string(input_area2) + ")");
  }
  return mesh;
}

}  // namespace

TriMesh mesh_planar(const Surface& surface, const MeshingOptions& options, const std::vector<Segment3>& contacts,
                    double contact_tolerance) {
  // A surface of 10^6 input polygons takes seconds to mesh: the steps below
  // call the caller's checkpoint every few thousand items.
  MeshingCheckpoint checkpoint(options.checkpoint);
  const PlaneFrame frame = plane_frame(surface);
  std::vector<Point2> q(surface.points.size());
  for (std::size_t i = 0; i < surface.points.size(); ++i) q[i] = frame.project(surface.points[i]);
  const InputTriangles input = input_triangles(surface, q, checkpoint);
  std::vector<Vec3> tri_normal;
  const double min_cos = min_cos_tilt(surface, input.triangles, frame.n, tri_normal, checkpoint);
  const ConstrainedRegion region = region_constraints(
      frame, q, input.triangles, polygon_constraints(surface, input.triangles, tri_normal, checkpoint), contacts,
      contact_tolerance);
  checkpoint();
  const PointLocator locator(q, input.triangles);
  checkpoint();

  // Leave room for the tilt: 2D bounds tight enough that the 3D mesh keeps
  // edges <= h and angles >= the requested minimum.
  const double tilt_angle_slack = 1.0 / min_cos - 1.0;
  const double min_angle_2d =
      std::min(options.min_angle_deg * kPi / 180.0 + tilt_angle_slack, kMaxMinAngleRad);
  const double shape_bound = std::pow(std::sin(min_angle_2d), 2);
  const double size_bound_2d = options.max_edge * min_cos * (1.0 - 1e-12);
  const RegionMesh mesh2 = refine_region(region, locator, shape_bound, size_bound_2d);
  checkpoint();
  return lift(surface, mesh2, locator, input.area, checkpoint);
}

}  // namespace lhr
