// data/blender_room/ as Blender 3.4.1's OBJ writer left it (made by
// tools/blender/make_room.py): what the script built must be what lhr loads,
// and the room must solve to a closed, lit, conforming result. The expected
// values below are the script's, converted to the OBJ's axes (Blender's z up
// becomes y up, Blender's y becomes −z).

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "io/image_io.hpp"
#include "io/mesh_io.hpp"
#include "io/scene_loader.hpp"
#include "mesh/validate.hpp"
#include "radiosity/classical_solver.hpp"
#include "radiosity/meshed_scene.hpp"
#include "test_support.hpp"

namespace lhr {
namespace {

const double kPi = 3.14159265358979323846;
const Vec3 kSphereCentre(-0.6, 0.6, -0.6);
const double kSphereRadius = 0.6;
const Vec3 kRoomCentre(0.0, 1.5, 0.0);  // 4 x 3 x 5 m, floor at y = 0
// Principled BSDF Emission (1, 0.9, 0.75) at Emission Strength 10.
const Rgb kLightRadiance(10.0, 9.0, 7.5);

std::filesystem::path room_scene() { return test::source_dir() / "data/blender_room/blender_room.scene.json"; }
std::filesystem::path room_obj() { return test::source_dir() / "data/blender_room/blender_room.obj"; }

// Newell's normal: the polygon's winding, whatever its shape.
Vec3 winding_normal(const PolygonSoup& soup, const InputFace& f) {
  Vec3 n(0, 0, 0);
  for (std::size_t i = 0; i < f.vertices.size(); ++i) {
    const Vec3& a = soup.points[f.vertices[i]];
    const Vec3& b = soup.points[f.vertices[(i + 1) % f.vertices.size()]];
    n += OpenMesh::cross(a, b);
  }
  return n.normalized();
}

Vec3 centroid(const PolygonSoup& soup, const InputFace& f) {
  Vec3 c(0, 0, 0);
  for (int v : f.vertices) c += soup.points[v];
  return c / static_cast<double>(f.vertices.size());
}

int group_index(const PolygonSoup& soup, const std::string& name) {
  const auto it = std::find(soup.groups.begin(), soup.groups.end(), name);
  return it == soup.groups.end() ? -1 : static_cast<int>(it - soup.groups.begin());
}

TEST(BlenderExport, ObjectsAndMaterialsAreWhatTheScriptBuilt) {
  std::vector<std::string> warnings;
  const PolygonSoup soup = load_polygon_soup(room_obj(), &warnings);
  EXPECT_EQ(std::set<std::string>(soup.groups.begin(), soup.groups.end()),
            (std::set<std::string>{"Room", "Sphere", "Block", "Light"}));
  std::map<std::string, Material> materials;
  for (const Material& m : soup.materials) materials[m.name] = m;
  ASSERT_EQ(materials.size(), 7u);
  for (const char* name : {"White", "RedWall", "GreenWall", "Floor", "Light", "Sphere", "Block"}) {
    EXPECT_EQ(materials.count(name), 1u) << name;
  }
  // Blender writes emission colour times strength as Ke, and Base Color as Kd.
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(materials["Light"].emission[c], kLightRadiance[c], 1e-6);
    EXPECT_NEAR(materials["Light"].reflectance[c], 0.8, 1e-6);
  }
  EXPECT_NEAR(materials["RedWall"].reflectance[0], 0.65, 1e-6);
  EXPECT_NEAR(materials["RedWall"].reflectance[1], 0.08, 1e-6);
  int emitters = 0;
  for (const auto& [name, m] : materials) emitters += m.is_emitter() ? 1 : 0;
  EXPECT_EQ(emitters, 1) << "Blender writes Ke 0 0 0 for every other material";
  // Blender's MTL carries the Principled BSDF's specular part as well, in
  // this order for every material; lhr names each of those keys once.
  int ignored = 0;
  for (const std::string& w : warnings) {
    if (w.find("ignored MTL keys") == std::string::npos) continue;
    ++ignored;
    EXPECT_NE(w.find("ignored MTL keys Ns, Ka, Ks, Ni, d, illum (in blender_room.mtl)"), std::string::npos) << w;
  }
  EXPECT_EQ(ignored, 1);
}

TEST(BlenderExport, SphereIsItsUvSegmentsWoundOutward) {
  const PolygonSoup soup = load_polygon_soup(room_obj());
  const int sphere = group_index(soup, "Sphere");
  ASSERT_GE(sphere, 0);
  int quads = 0, triangles = 0;
  for (const InputFace& f : soup.faces) {
    if (f.group != sphere) continue;
    (f.vertices.size() == 4 ? quads : triangles) += 1;
    for (int v : f.vertices) EXPECT_NEAR((soup.points[v] - kSphereCentre).norm(), kSphereRadius, 2e-6);
    EXPECT_GT(OpenMesh::dot(winding_normal(soup, f), (centroid(soup, f) - kSphereCentre).normalized()), 0.99)
        << "line " << f.source_line;
  }
  // 32 segments x 16 rings: quads between the rings, triangles at the poles
  // (the exporter was told not to triangulate).
  EXPECT_EQ(quads, 32 * 14);
  EXPECT_EQ(triangles, 2 * 32);
}

TEST(BlenderExport, RoomFacesInwardAndTheLightFacesTheFloor) {
  const PolygonSoup soup = load_polygon_soup(room_obj());
  const int room = group_index(soup, "Room"), light = group_index(soup, "Light"), block = group_index(soup, "Block");
  int walls = 0, lights = 0, block_faces = 0;
  for (const InputFace& f : soup.faces) {
    const Vec3 n = winding_normal(soup, f);
    if (f.group == room) {
      ++walls;
      EXPECT_GT(OpenMesh::dot(n, (kRoomCentre - centroid(soup, f)).normalized()), 0.5) << "line " << f.source_line;
    } else if (f.group == light) {
      ++lights;
      EXPECT_NEAR(n[1], -1.0, 1e-9);
      EXPECT_NEAR(centroid(soup, f)[1], 2.95, 1e-6);
    } else if (f.group == block) {
      ++block_faces;
    }
  }
  EXPECT_EQ(walls, 6);
  EXPECT_EQ(lights, 1);
  EXPECT_EQ(block_faces, 6);
}

TEST(BlenderExport, SceneFileLoadsWithOneSmoothSphereSurface) {
  const LoadResult load = load_scene(room_scene());
  const Scene& scene = load.scene;
  ASSERT_TRUE(scene.camera.has_value());
  EXPECT_EQ(scene.camera->width, 384);
  EXPECT_EQ(scene.camera->height, 288);
  // Six walls, one sphere, six block faces, one light: the sphere's faces
  // meet at 11.25 degrees, below the 30 degree crease angle.
  ASSERT_EQ(scene.surfaces.size(), 14u);
  int sphere_surfaces = 0, emitters = 0;
  for (const Surface& s : scene.surfaces) {
    if (s.name.rfind("Sphere/", 0) == 0) {
      ++sphere_surfaces;
      EXPECT_FALSE(s.planar);
      EXPECT_EQ(s.polygons.size(), 512u);
      // An inscribed polyhedron: a little less than the sphere's area.
      const double sphere_area = 4 * kPi * kSphereRadius * kSphereRadius;
      EXPECT_LT(s.area, sphere_area);
      EXPECT_GT(s.area, 0.98 * sphere_area);
    } else {
      EXPECT_TRUE(s.planar) << s.name;
    }
    if (scene.materials[s.material].is_emitter()) {
      ++emitters;
      EXPECT_NEAR(s.area, 1.0, 1e-9);
    }
  }
  EXPECT_EQ(sphere_surfaces, 1);
  EXPECT_EQ(emitters, 1);
}

// A closed room: every watt the light emits is absorbed somewhere, apart
// from the little that reaches the back of the light through the 5 cm gap
// under the ceiling (measured: absorbed 99.2 / 99.3 / 99.4 % of emitted,
// R/G/B). And every surface facing into the room gets light; the
// only one that does not is the block's bottom, which faces out of the room
// through the floor.
TEST(BlenderExport, ClosedRoomAbsorbsWhatTheLightEmitsAndEverySurfaceFacingItIsLit) {
  const LoadResult load = load_scene(room_scene());
  MeshingOptions meshing;
  meshing.max_edge = 0.5;
  MeshedScene model(load.scene, meshing);
  ClassicalOptions options;
  options.eps_bf = 0.01;
  options.tolerance = 1e-7;
  ClassicalSolver solver(model, options);
  solver.solve();
  Rgb emitted(0, 0, 0), absorbed(0, 0, 0);
  int dark = 0;
  for (int s = 0; s < model.num_surfaces(); ++s) {
    const Material& m = model.material(s);
    const Surface& surface = load.scene.surfaces[s];
    Rgb gathered(0, 0, 0);
    for (NodeId leaf : model.hierarchy(s).leaves()) {
      const double a = model.area(s, leaf);
      for (int c = 0; c < 3; ++c) {
        const double g = solver.gathered(s, leaf)[c];
        const double l = solver.radiance(s, leaf)[c];
        ASSERT_TRUE(std::isfinite(l) && l >= 0) << surface.name;
        emitted[c] += kPi * a * m.emission[c];
        absorbed[c] += kPi * a * (1.0 - m.reflectance[c]) * g;
        gathered[c] += a * g;
      }
    }
    const bool faces_out = surface.name.rfind("Block/", 0) == 0 && surface.normal[1] < -0.99;
    if (faces_out) {
      ++dark;
      EXPECT_EQ(gathered[0] + gathered[1] + gathered[2], 0.0) << surface.name;
    } else {
      EXPECT_GT(gathered[0] / surface.area, 1e-3) << surface.name << " receives no light";
    }
  }
  EXPECT_EQ(dark, 1);
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(emitted[c], kPi * kLightRadiance[c], 1e-9 * emitted[c]);
    EXPECT_NEAR(absorbed[c], emitted[c], 0.02 * emitted[c]) << "channel " << c;
  }
}

// `lhr solve` at coarse settings, then its outputs read back.
TEST(BlenderExport, SolvesToAConformingLitMeshAndAnImageShowingTheLight) {
  const auto dir = test::fresh_dir("blender_room");
  const auto r = test::run_lhr({"solve", room_scene().string(), "--out", (dir / "out").string(), "--max-edge", "0.5",
                                "--eps-link", "160", "--eps-pixel", "4", "--quiet"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const RawMesh mesh = read_raw_mesh(dir / "out" / "mesh.ply");
  ASSERT_EQ(mesh.radiance.size(), mesh.points.size());
  ConformingCheckOptions check;
  check.relative_tolerance = 1e-6;  // coordinates went through float storage
  const auto violations = check_conforming_mesh(mesh, check);
  EXPECT_TRUE(violations.empty()) << (violations.empty() ? "" : format_violation(violations.front()));
  for (const Rgb& l : mesh.radiance) {
    for (int c = 0; c < 3; ++c) ASSERT_TRUE(std::isfinite(l[c]) && l[c] >= 0);
  }
  // The camera sees the light: its brightest pixel is the emitted radiance
  // plus what the light's Kd 0.8 reflects of the room around it, which is
  // less than the emitted radiance.
  const Image exr = read_image(dir / "out" / "image.exr");
  float brightest = 0;
  for (float v : exr.rgb) brightest = std::max(brightest, v);
  EXPECT_GE(brightest, 10.0f - 0.02f);
  EXPECT_LT(brightest, 10.0f * 1.8f);
  // No pixel of the closed room is black: every surface the camera sees is lit.
  const std::size_t pixels = exr.rgb.size() / 3;
  std::size_t black = 0;
  for (std::size_t i = 0; i < pixels; ++i) {
    if (exr.rgb[3 * i] + exr.rgb[3 * i + 1] + exr.rgb[3 * i + 2] <= 0) ++black;
  }
  EXPECT_EQ(black, 0u);
}

}  // namespace
}  // namespace lhr
