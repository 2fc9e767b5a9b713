#pragma once
// Small scenes built in code for solver tests, and surfaces built in code
// for the initial-meshing tests.

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <map>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "mesh/hierarchy.hpp"
#include "mesh/initial_mesh.hpp"
#include "mesh/scene.hpp"
#include "mesh/surfaces.hpp"
#include "mesh/validate.hpp"
#include "radiosity/linear_solver.hpp"
#include "render/gouraud.hpp"

namespace lhr::test {

// A side x side grid of points in y = 0, 1 apart, two triangles per cell
// facing +y, one material and group: a soup large enough for the loaders'
// and the split's checkpoints to run many times.
inline PolygonSoup grid_soup(int side) {
  PolygonSoup soup;
  soup.materials = {Material{}};
  soup.groups = {"g"};
  for (int j = 0; j < side; ++j) {
    for (int i = 0; i < side; ++i) soup.points.emplace_back(i, 0, j);
  }
  for (int j = 0; j + 1 < side; ++j) {
    for (int i = 0; i + 1 < side; ++i) {
      const int a = j * side + i, b = a + 1, c = a + side, d = c + 1;
      soup.faces.push_back({{a, c, d}, 0, 0, 0});
      soup.faces.push_back({{a, d, b}, 0, 0, 0});
    }
  }
  return soup;
}

// Adds a quad (counter-clockwise seen from its front) to a soup.
inline void add_quad(PolygonSoup& soup, const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d, int material,
                     int group) {
  const int first = static_cast<int>(soup.points.size());
  for (const Vec3& p : {a, b, c, d}) soup.points.push_back(p);
  soup.faces.push_back({{first, first + 1, first + 2, first + 3}, material, group, 0});
}

// An axis-aligned box from lo to hi, six quads facing out, or in (a room).
inline void add_box(PolygonSoup& soup, const Vec3& lo, const Vec3& hi, bool inward, int material, int group) {
  const Vec3 c[8] = {Vec3(lo[0], lo[1], lo[2]), Vec3(hi[0], lo[1], lo[2]), Vec3(hi[0], lo[1], hi[2]),
                     Vec3(lo[0], lo[1], hi[2]), Vec3(lo[0], hi[1], lo[2]), Vec3(hi[0], hi[1], lo[2]),
                     Vec3(hi[0], hi[1], hi[2]), Vec3(lo[0], hi[1], hi[2])};
  const int faces[6][4] = {{0, 4, 5, 1}, {1, 5, 6, 2}, {2, 6, 7, 3}, {3, 7, 4, 0}, {4, 7, 6, 5}, {0, 1, 2, 3}};
  for (const auto& q : faces) {
    if (inward) {
      add_quad(soup, c[q[3]], c[q[2]], c[q[1]], c[q[0]], material, group);
    } else {
      add_quad(soup, c[q[0]], c[q[1]], c[q[2]], c[q[3]], material, group);
    }
  }
}

inline Scene scene_from_soup(const PolygonSoup& soup, const std::string& name) {
  Scene scene;
  scene.source = name;
  scene.materials = soup.materials;
  scene.surfaces = split_into_surfaces(soup, 30.0).surfaces;
  return scene;
}

// Closed unit cube, every face seen from inside: the top face (z = 1) gets
// `top`, the other five `walls`.
inline Scene closed_cube(const Material& walls, const Material& top, const std::string& name) {
  PolygonSoup soup;
  soup.materials = {walls, top};
  soup.groups = {"walls", "top"};
  const Vec3 p000(0, 0, 0), p100(1, 0, 0), p010(0, 1, 0), p110(1, 1, 0);
  const Vec3 p001(0, 0, 1), p101(1, 0, 1), p011(0, 1, 1), p111(1, 1, 1);
  add_quad(soup, p000, p100, p110, p010, 0, 0);  // z = 0, faces +z
  add_quad(soup, p001, p011, p111, p101, 1, 1);  // z = 1, faces −z
  add_quad(soup, p000, p001, p101, p100, 0, 0);  // y = 0, faces +y
  add_quad(soup, p010, p110, p111, p011, 0, 0);  // y = 1, faces −y
  add_quad(soup, p000, p010, p011, p001, 0, 0);  // x = 0, faces +x
  add_quad(soup, p100, p101, p111, p110, 0, 0);  // x = 1, faces −x
  return scene_from_soup(soup, name);
}

// Power absorbed by all surfaces: π ∫ (1 − ρ) E_in dA with E_in/π = (L − Le)/ρ,
// the linear interpolant integrated exactly over each leaf.
// A side × side grid of unit squares' corners in the plane y = 0, two roots
// per square, as one hierarchy.
inline SurfaceHierarchy grid_hierarchy(int side) {
  TriMesh mesh;
  std::vector<TriMesh::VertexHandle> vh;
  for (int j = 0; j < side; ++j) {
    for (int i = 0; i < side; ++i) vh.push_back(mesh.add_vertex(Vec3(i, 0, j)));
  }
  for (int j = 0; j + 1 < side; ++j) {
    for (int i = 0; i + 1 < side; ++i) {
      const int a = j * side + i, b = a + 1, c = a + side, d = c + 1;
      EXPECT_TRUE(mesh.add_face(vh[a], vh[c], vh[d]).is_valid());
      EXPECT_TRUE(mesh.add_face(vh[a], vh[d], vh[b]).is_valid());
    }
  }
  return SurfaceHierarchy(std::move(mesh));
}

inline Rgb absorbed_power(const MeshedScene& model, const std::function<std::vector<Rgb>(int)>& vertex_values) {
  Rgb absorbed(0, 0, 0);
  for (int s = 0; s < model.num_surfaces(); ++s) {
    const Material& m = model.material(s);
    const SurfaceHierarchy& h = model.hierarchy(s);
    const ConformingMesh mesh = h.conforming_mesh();
    const std::vector<Rgb> values = vertex_values(s);
    for (const auto fh : mesh.mesh.faces()) {
      Rgb mean(0, 0, 0);
      for (const auto vh : mesh.mesh.fv_range(fh)) mean += values[vh.idx()] / 3.0;
      const double a = mesh.mesh.calc_face_area(fh);
      for (int c = 0; c < 3; ++c) {
        if (m.reflectance[c] > 0) {
          absorbed[c] += M_PI * a * (1 - m.reflectance[c]) / m.reflectance[c] * (mean[c] - m.emission[c]);
        }
      }
    }
  }
  return absorbed;
}

// A grey material: reflectance rho and emission e in every channel.
inline Material grey_material(const std::string& name, double rho, double e = 0.0) {
  Material m;
  m.name = name;
  m.reflectance = Rgb(rho, rho, rho);
  m.emission = Rgb(e, e, e);
  return m;
}

// The furnace: every face the same material.
inline Scene furnace_cube(double reflectance, double emission) {
  const Material m = grey_material("furnace", reflectance, emission);
  return closed_cube(m, m, "furnace cube");
}

// A UV sphere of `lon` × `lat` segments (quads between rings, triangles at
// the poles), its faces facing the centre when `inward`, else outward.
inline void add_uv_sphere(PolygonSoup& soup, const Vec3& centre, double radius, int lon, int lat, bool inward,
                          int material, int group) {
  const int first = static_cast<int>(soup.points.size());
  soup.points.push_back(centre + Vec3(0, 0, radius));
  for (int i = 1; i < lat; ++i) {
    const double theta = M_PI * i / lat;
    for (int j = 0; j < lon; ++j) {
      const double phi = 2.0 * M_PI * j / lon;
      soup.points.push_back(centre + radius * Vec3(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi),
                                                   std::cos(theta)));
    }
  }
  soup.points.push_back(centre + Vec3(0, 0, -radius));
  const int south = static_cast<int>(soup.points.size()) - 1;
  const auto ring = [&](int i, int j) { return first + 1 + (i - 1) * lon + (j % lon); };
  const auto add = [&](std::vector<int> face) {
    // Orientation from geometry: the Newell normal must point away from the
    // centre for an outward face.
    Vec3 n(0, 0, 0), c(0, 0, 0);
    for (std::size_t k = 0; k < face.size(); ++k) {
      n += OpenMesh::cross(soup.points[face[k]], soup.points[face[(k + 1) % face.size()]]);
      c += soup.points[face[k]];
    }
    const bool outward = OpenMesh::dot(n, c / static_cast<double>(face.size()) - centre) > 0;
    if (outward == inward) std::reverse(face.begin(), face.end());
    soup.faces.push_back({face, material, group, 0});
  };
  for (int j = 0; j < lon; ++j) {
    add({first, ring(1, j), ring(1, j + 1)});
    for (int i = 1; i + 1 < lat; ++i) add({ring(i, j), ring(i + 1, j), ring(i + 1, j + 1), ring(i, j + 1)});
    add({south, ring(lat - 1, j + 1), ring(lat - 1, j)});
  }
}

// The furnace inside a sphere: one closed curved surface, ρ = 0.5, Le = 1.
inline Scene furnace_sphere() {
  PolygonSoup soup;
  soup.materials = {grey_material("furnace", 0.5, 1.0)};
  soup.groups = {"sphere"};
  add_uv_sphere(soup, Vec3(0, 0, 0), 1.0, 16, 8, true, 0, 0);
  return scene_from_soup(soup, "furnace sphere");
}

// A 1 × 10⁻⁴ strip (aspect 10⁴, ρ 0.8) standing across a unit floor (ρ 0.5)
// under a unit light (Le 1) at height 1, facing down.
inline Scene sliver_on_lit_floor() {
  PolygonSoup soup;
  soup.materials = {grey_material("floor", 0.5), grey_material("light", 0.0, 1.0), grey_material("strip", 0.8)};
  soup.groups = {"floor", "light", "strip"};
  add_quad(soup, Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0), 0, 0);
  add_quad(soup, Vec3(0, 0, 1), Vec3(0, 1, 1), Vec3(1, 1, 1), Vec3(1, 0, 1), 1, 1);
  add_quad(soup, Vec3(0, 0.5, 0), Vec3(1, 0.5, 0), Vec3(1, 0.5, 1e-4), Vec3(0, 0.5, 1e-4), 2, 2);
  return scene_from_soup(soup, "sliver");
}

// A square emitter (Kd 0) of side `size` at height `height`, facing down,
// centred over a unit receiver square in z = 0 facing up.
inline Scene emitter_over_receiver(double size, double height, double receiver_reflectance, double emission) {
  PolygonSoup soup;
  Material receiver;
  receiver.name = "receiver";
  receiver.reflectance = Rgb(receiver_reflectance, receiver_reflectance, receiver_reflectance);
  Material light;
  light.name = "light";
  light.reflectance = Rgb(0, 0, 0);
  light.emission = Rgb(emission, emission, emission);
  soup.materials = {receiver, light};
  soup.groups = {"receiver", "light"};
  add_quad(soup, Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0), 0, 0);
  const double lo = 0.5 - size / 2, hi = 0.5 + size / 2;
  add_quad(soup, Vec3(lo, lo, height), Vec3(lo, hi, height), Vec3(hi, hi, height), Vec3(hi, lo, height), 1, 1);
  return scene_from_soup(soup, "emitter over receiver");
}

// A triangle mesh as check_conforming_mesh reads it, with optional per-vertex values.
inline RawMesh raw_mesh(const TriMesh& mesh, const std::vector<Rgb>& values = {}) {
  RawMesh raw;
  for (const auto vh : mesh.vertices()) raw.points.push_back(mesh.point(vh));
  for (const auto fh : mesh.faces()) {
    std::vector<int> f;
    for (const auto vh : mesh.fv_range(fh)) f.push_back(vh.idx());
    raw.faces.push_back(f);
  }
  raw.radiance = values;
  return raw;
}

// What `camera` sees, for the linear solver's importance.
inline std::vector<ViewSample> view_from(const MeshedScene& model, const Camera& camera) {
  std::vector<const TriMesh*> meshes;
  for (int s = 0; s < model.num_surfaces(); ++s) meshes.push_back(&model.hierarchy(s).mesh());
  return view_samples(camera, meshes);
}

// What a camera at `eye` looking at `target` sees, width x height pixels.
inline std::vector<ViewSample> view_from(const MeshedScene& model, const Vec3& eye, const Vec3& target, const Vec3& up,
                                         double fov_y_deg, int width, int height) {
  Camera camera;
  camera.eye = eye;
  camera.target = target;
  camera.up = up;
  camera.fov_y_deg = fov_y_deg;
  camera.width = width;
  camera.height = height;
  return view_from(model, camera);
}

// What the scene camera (or the framing camera) sees: at size x size pixels
// when size > 0, else its own.
inline std::vector<ViewSample> camera_view(const MeshedScene& model, int size) {
  Camera camera = model.scene().camera.value_or(framing_camera(model.scene()));
  if (size > 0) camera.width = camera.height = size;
  return view_from(model, camera);
}

// Quick linear-solver settings for a scene seen by its camera at size x size
// pixels: the given thresholds, 2 x 2 shadow rays a link.
inline LinearOptions quick_linear_options(const MeshedScene& model, double eps_link, double eps_pixel, int size) {
  LinearOptions options;
  options.eps_link = eps_link;
  options.eps_pixel = eps_pixel;
  options.visibility_samples = 2;
  options.view = camera_view(model, size);
  return options;
}

// ---------------------------------------------------------------------------
// Initial meshing (test_planar_mesh, test_curved_mesh, test_initial_mesh):
// input surfaces built in code, and what those tests measure of a mesh, each
// computed here independently of the mesher.

inline constexpr double kPi = 3.14159265358979323846;

// Lambert's closed form for the form factor from a point x with unit normal
// n to a convex polygon wholly in front of it: the truth the light-over-a-
// receiver tests compare with, written here apart from radiosity/form_factor.
inline double lambert_form_factor(const Vec3& x, const Vec3& n, const std::array<Vec3, 4>& polygon) {
  double sum = 0.0;
  for (std::size_t i = 0; i < polygon.size(); ++i) {
    const Vec3 a = (polygon[i] - x).normalized();
    const Vec3 b = (polygon[(i + 1) % polygon.size()] - x).normalized();
    const double angle = std::acos(std::clamp(a.dot(b), -1.0, 1.0));
    const Vec3 c = a.cross(b);
    const double norm = c.norm();
    if (norm > 0) sum += angle * n.dot(c / norm);
  }
  return std::abs(sum) / (2.0 * kPi);
}

inline double deg(double rad) { return rad * 180.0 / kPi; }

inline Vec3 vector_area(const std::vector<Vec3>& points, const std::vector<std::vector<int>>& polygons) {
  Vec3 sum(0, 0, 0);
  for (const auto& poly : polygons) {
    for (std::size_t i = 1; i + 1 < poly.size(); ++i) {
      sum += 0.5 * OpenMesh::cross(points[poly[i]] - points[poly[0]], points[poly[i + 1]] - points[poly[0]]);
    }
  }
  return sum;
}

// Area of the polygons' fan triangulations: the piecewise-linear shape a
// slightly non-planar quad stands for.
inline double fan_area(const Surface& s) {
  double area = 0.0;
  for (const auto& poly : s.polygons) {
    for (std::size_t i = 1; i + 1 < poly.size(); ++i) {
      area += 0.5 * OpenMesh::cross(s.points[poly[i]] - s.points[poly[0]], s.points[poly[i + 1]] - s.points[poly[0]]).norm();
    }
  }
  return area;
}

inline Surface make_surface(std::string name, std::vector<Vec3> points, std::vector<std::vector<int>> polygons,
                            bool planar) {
  Surface s;
  s.name = std::move(name);
  s.points = std::move(points);
  s.polygons = std::move(polygons);
  s.planar = planar;
  const Vec3 a = vector_area(s.points, s.polygons);
  s.normal = a.normalized();
  s.area = fan_area(s);
  return s;
}

// The unit square in z = 0, facing +z, as one quad.
inline Surface unit_square() {
  return make_surface("square", {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}, {{0, 1, 2, 3}}, true);
}

// Meshing options with h = max_edge and the other options at their defaults.
inline MeshingOptions with_h(double h) {
  MeshingOptions o;
  o.max_edge = h;
  return o;
}

inline double mesh_area(const TriMesh& m) {
  double a = 0.0;
  for (const auto f : m.faces()) {
    auto it = m.cfv_iter(f);
    const Vec3 p0 = m.point(*it++), p1 = m.point(*it++), p2 = m.point(*it);
    a += 0.5 * OpenMesh::cross(p1 - p0, p2 - p0).norm();
  }
  return a;
}

inline std::array<Vec3, 3> corners(const TriMesh& m, TriMesh::FaceHandle f) {
  auto it = m.cfv_iter(f);
  const Vec3 p0 = m.point(*it++), p1 = m.point(*it++), p2 = m.point(*it);
  return {p0, p1, p2};
}

inline double max_edge_length(const TriMesh& m) {
  double l = 0.0;
  for (const auto e : m.edges()) l = std::max(l, m.calc_edge_length(e));
  return l;
}

struct Segment {
  Vec3 a, b;
};

inline double distance_to_segment(const Vec3& p, const Segment& s) {
  const Vec3 d = s.b - s.a;
  const double t = std::clamp(OpenMesh::dot(p - s.a, d) / d.sqrnorm(), 0.0, 1.0);
  return (p - (s.a + t * d)).norm();
}

// How many polygons use each undirected edge (a pair of point indices).
inline std::map<std::pair<int, int>, int> edge_uses(const Surface& s) {
  std::map<std::pair<int, int>, int> uses;
  for (const auto& poly : s.polygons) {
    for (std::size_t i = 0; i < poly.size(); ++i) ++uses[std::minmax(poly[i], poly[(i + 1) % poly.size()])];
  }
  return uses;
}

// Undirected polygon edges used by exactly one polygon.
inline std::vector<Segment> input_boundary(const Surface& s) {
  std::vector<Segment> out;
  for (const auto& [e, n] : edge_uses(s)) {
    if (n == 1) out.push_back({s.points[e.first], s.points[e.second]});
  }
  return out;
}

inline std::set<int> input_boundary_vertices(const Surface& s) {
  std::set<int> out;
  for (const auto& [e, n] : edge_uses(s)) {
    if (n == 1) {
      out.insert(e.first);
      out.insert(e.second);
    }
  }
  return out;
}

inline double smallest_angle(const std::array<Vec3, 3>& c) {
  double m = kPi;
  for (int k = 0; k < 3; ++k) {
    const Vec3 a = c[(k + 1) % 3] - c[k], b = c[(k + 2) % 3] - c[k];
    m = std::min(m, std::atan2(OpenMesh::cross(a, b).norm(), OpenMesh::dot(a, b)));
  }
  return m;
}

inline void expect_no_duplicate_vertices(const TriMesh& m) {
  std::set<std::array<double, 3>> seen;
  for (const auto v : m.vertices()) {
    const Vec3& p = m.point(v);
    EXPECT_TRUE(seen.insert({p[0], p[1], p[2]}).second) << "duplicate vertex at " << p;
  }
}

}  // namespace lhr::test
