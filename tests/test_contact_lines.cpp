// Contact lines (mesh/contact_lines.hpp): where a surface touches or crosses
// a planar one, the planar surface's initial mesh has edges, so that no
// element straddles the jump in radiance there. Every expectation follows
// from the constructed geometry (footprints, planes), not from earlier runs.

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "mesh/contact_lines.hpp"
#include "mesh/initial_mesh.hpp"

namespace lhr {
namespace {

Surface planar_surface(std::vector<Vec3> points, std::vector<std::vector<int>> polygons) {
  Surface s;
  s.name = std::string("planar");
  s.points = std::move(points);
  s.polygons = std::move(polygons);
  s.planar = true;
  Vec3 a(0, 0, 0);
  for (const auto& poly : s.polygons) {
    for (std::size_t i = 1; i + 1 < poly.size(); ++i) {
      a += 0.5 * OpenMesh::cross(s.points[poly[i]] - s.points[poly[0]], s.points[poly[i + 1]] - s.points[poly[0]]);
    }
  }
  s.area = a.norm();
  s.normal = a.normalized();
  return s;
}

// The 10 x 10 floor y = 0, facing +y.
Surface floor_quad() {
  return planar_surface({{0, 0, 0}, {0, 0, 10}, {10, 0, 10}, {10, 0, 0}}, {{0, 1, 2, 3}});
}

// An open-bottomed box over the rectangle [x0, x1] x [z0, z1] from height
// y0 to y1: four sides and a top, each its own surface, facing out.
std::vector<Surface> box(double x0, double x1, double z0, double z1, double y0, double y1) {
  const std::array<Vec3, 8> c{Vec3(x0, y0, z0), Vec3(x1, y0, z0), Vec3(x1, y0, z1), Vec3(x0, y0, z1),
                              Vec3(x0, y1, z0), Vec3(x1, y1, z0), Vec3(x1, y1, z1), Vec3(x0, y1, z1)};
  const std::array<std::array<int, 4>, 5> faces{{{0, 4, 5, 1}, {1, 5, 6, 2}, {2, 6, 7, 3}, {3, 7, 4, 0}, {4, 7, 6, 5}}};
  std::vector<Surface> out;
  for (const auto& f : faces) out.push_back(planar_surface({c[f[0]], c[f[1]], c[f[2]], c[f[3]]}, {{0, 1, 2, 3}}));
  return out;
}

std::vector<Surface> with(Surface first, const std::vector<Surface>& rest) {
  std::vector<Surface> all{std::move(first)};
  all.insert(all.end(), rest.begin(), rest.end());
  return all;
}

// Whether the floor mesh keeps every triangle on one side of the rectangle's
// outline: none has one corner strictly inside and one strictly outside.
bool respects_rectangle(const TriMesh& mesh, double x0, double x1, double z0, double z1, double slack) {
  for (const auto f : mesh.faces()) {
    bool in = false, out = false;
    for (const auto v : mesh.fv_range(f)) {
      const Vec3& p = mesh.point(v);
      in |= p[0] > x0 + slack && p[0] < x1 - slack && p[2] > z0 + slack && p[2] < z1 - slack;
      out |= p[0] < x0 - slack || p[0] > x1 + slack || p[2] < z0 - slack || p[2] > z1 + slack;
    }
    if (in && out) return false;
  }
  return true;
}

bool has_vertex_at(const TriMesh& mesh, const Vec3& p, double slack) {
  return std::any_of(mesh.vertices().begin(), mesh.vertices().end(),
                     [&](const auto v) { return (mesh.point(v) - p).norm() <= slack; });
}

double mesh_area(const TriMesh& mesh) {
  double a = 0.0;
  for (const auto f : mesh.faces()) a += mesh.calc_face_area(f);
  return a;
}

double total_length(const std::vector<Segment3>& segments) {
  double l = 0.0;
  for (const auto& s : segments) l += (s[1] - s[0]).norm();
  return l;
}

MeshingOptions options(double h) {
  MeshingOptions o;
  o.max_edge = h;
  return o;
}

TEST(ContactLines, BoxStandingOnAFloorLeavesItsFootprintInTheFloorMesh) {
  const auto surfaces = with(floor_quad(), box(2.3, 4.1, 3.7, 6.2, 0.0, 1.5));
  const double tolerance = contact_tolerance(surfaces);
  const auto contacts = find_contact_lines(surfaces, tolerance);
  // The four feet of the sides, each found once: the footprint's perimeter.
  EXPECT_NEAR(total_length(contacts[0]), 2 * (1.8 + 2.5), 1e-9);

  const TriMesh without = mesh_surface(surfaces[0], options(2.0));
  const TriMesh mesh = mesh_surface(surfaces[0], options(2.0), contacts[0], tolerance);
  EXPECT_FALSE(respects_rectangle(without, 2.3, 4.1, 3.7, 6.2, 1e-9)) << "the test needs a footprint the plain mesh cuts";
  EXPECT_TRUE(respects_rectangle(mesh, 2.3, 4.1, 3.7, 6.2, 1e-9));
  for (const Vec3 corner : {Vec3(2.3, 0, 3.7), Vec3(4.1, 0, 3.7), Vec3(4.1, 0, 6.2), Vec3(2.3, 0, 6.2)}) {
    EXPECT_TRUE(has_vertex_at(mesh, corner, 1e-9)) << corner;
  }
  EXPECT_NEAR(mesh_area(mesh), 100.0, 1e-9);
  for (const auto v : mesh.vertices()) EXPECT_NEAR(mesh.point(v)[1], 0.0, 1e-12);
}

TEST(ContactLines, NothingTouchesWhenTheBoxFloatsOrStandsBehindTheFloor) {
  for (const double y0 : {0.05, -2.0}) {
    const auto surfaces = with(floor_quad(), box(2.3, 4.1, 3.7, 6.2, y0, y0 + 1.5));
    EXPECT_TRUE(find_contact_lines(surfaces, contact_tolerance(surfaces))[0].empty()) << "box from y = " << y0;
  }
}

TEST(ContactLines, ABoxSunkIntoTheFloorIsCutAlongWhereItCrossesIt) {
  const auto surfaces = with(floor_quad(), box(2.0, 5.0, 2.0, 4.0, -0.7, 1.0));
  const double tolerance = contact_tolerance(surfaces);
  const auto contacts = find_contact_lines(surfaces, tolerance);
  EXPECT_NEAR(total_length(contacts[0]), 2 * (3.0 + 2.0), 1e-9);
  const TriMesh mesh = mesh_surface(surfaces[0], options(2.5), contacts[0], tolerance);
  EXPECT_TRUE(respects_rectangle(mesh, 2.0, 5.0, 2.0, 4.0, 1e-9));
}

TEST(ContactLines, ALightJustBelowItsCeilingLeavesNoOutline) {
  // The ceiling y = 3 faces down; the light, a little below, faces down too
  // (as after the loader lifts a light drawn on its ceiling). The ceiling
  // darkens toward the light's edge only within that gap, so the edge is not
  // a line to mesh: a node on it would shade an element beside the lamp.
  const Surface ceiling = planar_surface({{0, 3, 0}, {10, 3, 0}, {10, 3, 10}, {0, 3, 10}}, {{0, 1, 2, 3}});
  const double lift = 1e-4 * std::sqrt(10 * 10 + 10 * 10 + 3 * 3);
  const double y = 3 - lift;
  const Surface light = planar_surface({{4, y, 4}, {6, y, 4}, {6, y, 7}, {4, y, 7}}, {{0, 1, 2, 3}});
  ASSERT_LT(ceiling.normal[1], -0.99);
  ASSERT_LT(light.normal[1], -0.99);
  const std::vector<Surface> surfaces{ceiling, light};
  const double tolerance = contact_tolerance(surfaces);
  ASSERT_GT(tolerance, lift) << "the light counts as lying on the ceiling";
  EXPECT_TRUE(find_contact_lines(surfaces, tolerance)[0].empty());
}

TEST(ContactLines, BoxesPushedIntoEachOtherAndAgainstTheWallMeshCleanly) {
  // Two footprints that cross each other, one flush with the floor's edge
  // x = 0 and one reaching past the edge z = 10.
  auto a = box(0.0, 3.0, 2.0, 5.0, 0.0, 1.0);
  const auto b = box(2.0, 6.0, 4.0, 11.0, 0.0, 2.0);
  a.insert(a.end(), b.begin(), b.end());
  const auto surfaces = with(floor_quad(), a);
  const double tolerance = contact_tolerance(surfaces);
  const auto contacts = find_contact_lines(surfaces, tolerance);
  const TriMesh without = mesh_surface(surfaces[0], options(2.0));
  const TriMesh mesh = mesh_surface(surfaces[0], options(2.0), contacts[0], tolerance);
  ASSERT_GT(mesh.n_vertices(), without.n_vertices());
  EXPECT_TRUE(respects_rectangle(mesh, 0.0, 3.0, 2.0, 5.0, 1e-9));
  EXPECT_TRUE(respects_rectangle(mesh, 2.0, 6.0, 4.0, 11.0, 1e-9));
  EXPECT_NEAR(mesh_area(mesh), 100.0, 1e-9);
  EXPECT_TRUE(has_vertex_at(mesh, Vec3(2.0, 0, 5.0), 1e-9)) << "where the footprints cross";
  EXPECT_TRUE(has_vertex_at(mesh, Vec3(2.0, 0, 10.0), 1e-9)) << "where a footprint leaves the floor";
}

TEST(ContactLines, CurvedSurfacesAndLoneSurfacesHaveNone) {
  Surface curved = floor_quad();
  curved.planar = false;
  const auto contacts = find_contact_lines(with(curved, box(2, 4, 2, 4, 0, 1)), 1e-2);
  EXPECT_TRUE(contacts[0].empty());
  EXPECT_TRUE(find_contact_lines({floor_quad()}, 1e-2)[0].empty());
}

}  // namespace
}  // namespace lhr
