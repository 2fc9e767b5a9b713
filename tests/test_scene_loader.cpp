// Scene loading and surface splitting (docs/design.md §3): what a user's OBJ/MTL,
// PLY, OFF and scene JSON turn into.

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "io/image_io.hpp"
#include "io/scene_loader.hpp"
#include "mesh/surfaces.hpp"
#include "test_support.hpp"

namespace lhr {
namespace {

using test::fresh_dir;
using test::write_text;

// Unit cube [0,1]^3 with outward, counter-clockwise faces.
const char* const kCubeVertices =
    "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
    "v 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n";
const std::array<std::array<int, 4>, 6> kCubeQuads{{
    {1, 4, 3, 2},  // z = 0, normal -z
    {5, 6, 7, 8},  // z = 1, +z
    {1, 2, 6, 5},  // y = 0, -y
    {4, 8, 7, 3},  // y = 1, +y
    {1, 5, 8, 4},  // x = 0, -x
    {2, 3, 7, 6},  // x = 1, +x
}};

std::string cube_as_quads() {
  std::string obj = kCubeVertices;
  for (const auto& q : kCubeQuads) {
    obj += "f " + std::to_string(q[0]) + " " + std::to_string(q[1]) + " " + std::to_string(q[2]) + " " +
           std::to_string(q[3]) + "\n";
  }
  return obj;
}

std::string cube_as_triangles() {
  std::string obj = kCubeVertices;
  for (const auto& q : kCubeQuads) {
    obj += "f " + std::to_string(q[0]) + " " + std::to_string(q[1]) + " " + std::to_string(q[2]) + "\n";
    obj += "f " + std::to_string(q[0]) + " " + std::to_string(q[2]) + " " + std::to_string(q[3]) + "\n";
  }
  return obj;
}

// Icosahedron subdivided `levels` times, projected to the unit sphere;
// 20 * 4^levels outward triangles.
std::string icosphere(int levels, bool duplicate_vertices) {
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<Vec3> p{{-1, t, 0},  {1, t, 0},  {-1, -t, 0}, {1, -t, 0}, {0, -1, t},  {0, 1, t},
                      {0, -1, -t}, {0, 1, -t}, {t, 0, -1},  {t, 0, 1},  {-t, 0, -1}, {-t, 0, 1}};
  for (Vec3& v : p) v.normalize();
  std::vector<std::array<int, 3>> f{{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                                    {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                    {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                                    {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  for (int l = 0; l < levels; ++l) {
    std::map<std::pair<int, int>, int> mid;
    auto midpoint = [&](int a, int b) {
      const auto key = std::minmax(a, b);
      auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      p.push_back((0.5 * (p[a] + p[b])).normalized());
      return mid[key] = static_cast<int>(p.size()) - 1;
    };
    std::vector<std::array<int, 3>> next;
    for (const auto& tri : f) {
      const int ab = midpoint(tri[0], tri[1]), bc = midpoint(tri[1], tri[2]), ca = midpoint(tri[2], tri[0]);
      next.push_back({tri[0], ab, ca});
      next.push_back({tri[1], bc, ab});
      next.push_back({tri[2], ca, bc});
      next.push_back({ab, bc, ca});
    }
    f = next;
  }
  std::ostringstream obj;
  obj.precision(17);
  if (duplicate_vertices) {
    int n = 0;
    for (const auto& tri : f) {
      for (int k : tri) obj << "v " << p[k][0] << ' ' << p[k][1] << ' ' << p[k][2] << '\n';
      obj << "f " << n + 1 << ' ' << n + 2 << ' ' << n + 3 << '\n';
      n += 3;
    }
  } else {
    for (const Vec3& v : p) obj << "v " << v[0] << ' ' << v[1] << ' ' << v[2] << '\n';
    for (const auto& tri : f) obj << "f " << tri[0] + 1 << ' ' << tri[1] + 1 << ' ' << tri[2] + 1 << '\n';
  }
  return obj.str();
}

std::filesystem::path write(const std::string& dir, const std::string& name, const std::string& text) {
  const auto path = fresh_dir(dir) / name;
  write_text(path, text);
  return path;
}

TEST(SceneLoader, OneMaterialBoxOfQuadsIsSixPlanarUnitSurfaces) {
  const Scene scene = load_scene(write("box_quads", "box.obj", cube_as_quads())).scene;
  ASSERT_EQ(scene.surfaces.size(), 6u);
  std::set<std::array<int, 3>> normals;
  for (const Surface& s : scene.surfaces) {
    EXPECT_TRUE(s.planar) << s.name;
    EXPECT_NEAR(s.area, 1.0, 1e-12) << s.name;
    EXPECT_EQ(s.polygons.size(), 1u);
    EXPECT_EQ(s.points.size(), 4u);
    EXPECT_NEAR(s.normal.norm(), 1.0, 1e-12);
    normals.insert({static_cast<int>(std::lround(s.normal[0])), static_cast<int>(std::lround(s.normal[1])),
                    static_cast<int>(std::lround(s.normal[2]))});
  }
  // Six distinct axis directions: each face kept its outward orientation.
  EXPECT_EQ(normals.size(), 6u);
  EXPECT_EQ(scene.surfaces[0].name, "default/default#0");
  EXPECT_EQ(scene.surfaces[5].name, "default/default#5");
  // Input order is kept: the first quad is the z = 0 face, seen from below.
  EXPECT_NEAR(scene.surfaces[0].normal[2], -1.0, 1e-12);
  ASSERT_EQ(scene.materials.size(), 1u);
  EXPECT_EQ(scene.materials[0].reflectance, Rgb(0.5, 0.5, 0.5));
  EXPECT_FALSE(scene.materials[0].is_emitter());
}

TEST(SceneLoader, BoxOfTwelveTrianglesIsSixSurfacesOfTwo) {
  const Scene scene = load_scene(write("box_tris", "box.obj", cube_as_triangles())).scene;
  ASSERT_EQ(scene.surfaces.size(), 6u);
  for (const Surface& s : scene.surfaces) {
    EXPECT_EQ(s.polygons.size(), 2u);
    EXPECT_EQ(s.points.size(), 4u);
    EXPECT_TRUE(s.planar);
    EXPECT_NEAR(s.area, 1.0, 1e-12);
  }
}

TEST(SceneLoader, TessellatedSphereIsOneCurvedSurface) {
  const auto path = write("sphere", "sphere.obj", icosphere(2, false));
  const Scene scene = load_scene(path).scene;
  ASSERT_EQ(scene.surfaces.size(), 1u);
  const Surface& s = scene.surfaces[0];
  EXPECT_FALSE(s.planar);
  EXPECT_EQ(s.polygons.size(), 320u);
  // Closed icosphere: V - E + F = 2 with E = 3F/2.
  EXPECT_EQ(s.points.size(), 162u);
  // Inscribed polyhedron: a little less than the sphere's 4*pi.
  EXPECT_LT(s.area, 4.0 * M_PI);
  EXPECT_GT(s.area, 0.95 * 4.0 * M_PI);
  EXPECT_NEAR(s.normal.norm(), 1.0, 1e-9);
}

TEST(SceneLoader, CreaseAngleOverrideChangesTheSplit) {
  // Adjacent faces of a level-2 icosphere meet at several degrees, so a 1°
  // crease angle cuts along every edge: one surface per face.
  const auto path = write("sphere_crease", "sphere.obj", icosphere(2, false));
  LoadOptions options;
  options.crease_angle_deg = 1.0;
  EXPECT_EQ(load_scene(path, options).scene.surfaces.size(), 320u);

  // The scene file's setting applies unless the options override it.
  const auto json = path.parent_path() / "sphere.scene.json";
  write_text(json, R"({"mesh": "sphere.obj", "meshing": {"crease_angle_deg": 1}})");
  const LoadResult from_file = load_scene(json);
  EXPECT_EQ(from_file.scene.surfaces.size(), 320u);
  ASSERT_TRUE(from_file.scene.settings.crease_angle_deg.has_value());
  EXPECT_EQ(*from_file.scene.settings.crease_angle_deg, 1.0);
  options.crease_angle_deg = 30.0;
  EXPECT_EQ(load_scene(json, options).scene.surfaces.size(), 1u);

  // A box has 90° creases: 6 surfaces below 90°, one above.
  const auto box = write("box_crease", "box.obj", cube_as_quads());
  options.crease_angle_deg = 89.0;
  EXPECT_EQ(load_scene(box, options).scene.surfaces.size(), 6u);
  options.crease_angle_deg = 91.0;
  EXPECT_EQ(load_scene(box, options).scene.surfaces.size(), 1u);
}

TEST(SceneLoader, GroupsAndMaterialsSeparateSurfacesAndMtlIsParsed) {
  const auto dir = fresh_dir("groups");
  write_text(dir / "room.mtl",
             "newmtl white\nKd 0.8 0.7 0.6\n\n"
             "newmtl lamp\nKd 0.1 0.2 0.3\nKe 10 20 30\n");
  // Two coplanar quads sharing an edge: only the group/material cut them.
  write_text(dir / "room.obj",
             "mtllib room.mtl\n"
             "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\nv 2 1 0\n"
             "o floor\nusemtl white\nf 1 2 3 4\n"
             "o light\nusemtl lamp\nf 2 5 6 3\n");
  const Scene scene = load_scene(dir / "room.obj").scene;
  ASSERT_EQ(scene.surfaces.size(), 2u);
  EXPECT_EQ(scene.surfaces[0].name, "floor/white#0");
  EXPECT_EQ(scene.surfaces[1].name, "light/lamp#0");
  const Material& white = scene.materials.at(scene.surfaces[0].material);
  const Material& lamp = scene.materials.at(scene.surfaces[1].material);
  EXPECT_LT((white.reflectance - Rgb(0.8, 0.7, 0.6)).norm(), 1e-12);
  EXPECT_FALSE(white.is_emitter());
  EXPECT_LT((lamp.reflectance - Rgb(0.1, 0.2, 0.3)).norm(), 1e-12);
  EXPECT_LT((lamp.emission - Rgb(10, 20, 30)).norm(), 1e-12);
  EXPECT_TRUE(lamp.is_emitter());

  // The same faces in one group with one material form one surface.
  write_text(dir / "one.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\nv 2 1 0\nf 1 2 3 4\nf 2 5 6 3\n");
  const Scene one = load_scene(dir / "one.obj").scene;
  ASSERT_EQ(one.surfaces.size(), 1u);
  EXPECT_EQ(one.surfaces[0].points.size(), 6u);
  EXPECT_NEAR(one.surfaces[0].area, 2.0, 1e-12);
}

TEST(SceneLoader, SceneFileCameraAndSettingsAreParsed) {
  const auto dir = fresh_dir("camera");
  write_text(dir / "box.obj", cube_as_quads());
  write_text(dir / "box.scene.json", R"({
    "mesh": "box.obj",
    "camera": {"eye": [0.5, 0.5, 3], "target": [0.5, 0.5, 0.5], "up": [0, 1, 0],
               "fov_y_deg": 40, "width": 320, "height": 240},
    "meshing": {"max_edge": 0.25}
  })");
  const LoadResult loaded = load_scene(dir / "box.scene.json");
  const Scene& scene = loaded.scene;
  ASSERT_TRUE(scene.camera.has_value());
  EXPECT_EQ(scene.camera->eye, Vec3(0.5, 0.5, 3));
  EXPECT_EQ(scene.camera->target, Vec3(0.5, 0.5, 0.5));
  EXPECT_EQ(scene.camera->up, Vec3(0, 1, 0));
  EXPECT_EQ(scene.camera->fov_y_deg, 40.0);
  EXPECT_EQ(scene.camera->width, 320);
  EXPECT_EQ(scene.camera->height, 240);
  ASSERT_TRUE(scene.settings.max_edge.has_value());
  EXPECT_EQ(*scene.settings.max_edge, 0.25);
  EXPECT_FALSE(scene.settings.crease_angle_deg.has_value());
  EXPECT_EQ(scene.surfaces.size(), 6u);
  EXPECT_EQ(scene.source, (dir / "box.scene.json").string());
  EXPECT_TRUE(loaded.warnings.empty());
}

TEST(SceneLoader, BareGeometryGetsTheFramingCamera) {
  const Scene scene = load_scene(write("framing", "box.obj", cube_as_quads())).scene;
  ASSERT_TRUE(scene.camera.has_value());
  const Camera expected = framing_camera(scene);
  EXPECT_EQ(scene.camera->eye, expected.eye);
  EXPECT_EQ(scene.camera->target, Vec3(0.5, 0.5, 0.5));
}

TEST(SceneLoader, PolygonsWithFiveAndMoreVerticesAreKeptWhole) {
  // Regular pentagon and hexagon of circumradius 1 in separate planes.
  std::ostringstream obj;
  obj.precision(17);
  for (int k = 0; k < 5; ++k) {
    obj << "v " << std::cos(2 * M_PI * k / 5) << ' ' << std::sin(2 * M_PI * k / 5) << " 0\n";
  }
  for (int k = 0; k < 6; ++k) {
    obj << "v " << std::cos(2 * M_PI * k / 6) << ' ' << std::sin(2 * M_PI * k / 6) << " 5\n";
  }
  obj << "f 1 2 3 4 5\nf 6 7 8 9 10 11\n";
  const Scene scene = load_scene(write("ngons", "ngons.obj", obj.str())).scene;
  ASSERT_EQ(scene.surfaces.size(), 2u);
  ASSERT_EQ(scene.surfaces[0].polygons.size(), 1u);
  EXPECT_EQ(scene.surfaces[0].polygons[0], (std::vector<int>{0, 1, 2, 3, 4}));
  EXPECT_EQ(scene.surfaces[1].polygons[0].size(), 6u);
  EXPECT_NEAR(scene.surfaces[0].area, 2.5 * std::sin(2 * M_PI / 5), 1e-12);
  EXPECT_NEAR(scene.surfaces[1].area, 3.0 * std::sin(2 * M_PI / 6), 1e-12);
  EXPECT_NEAR(scene.surfaces[0].normal[2], 1.0, 1e-12);
  EXPECT_TRUE(scene.surfaces[0].planar);
}

TEST(SceneLoader, DuplicatedPositionVerticesAreWelded) {
  // Every triangle of the sphere has its own three vertices, as many
  // exporters write them; it must still be one surface with shared points.
  const Scene scene = load_scene(write("welded_sphere", "sphere.obj", icosphere(1, true))).scene;
  ASSERT_EQ(scene.surfaces.size(), 1u);
  EXPECT_EQ(scene.surfaces[0].polygons.size(), 80u);
  EXPECT_EQ(scene.surfaces[0].points.size(), 42u);  // V = E - F + 2 = 120 - 80 + 2

  // A quad written as two triangles with six distinct vertices.
  const Scene quad = load_scene(write("welded_quad", "quad.obj",
                                      "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 0 0\nv 1 1 0\nv 0 1 0\n"
                                      "f 1 2 3\nf 4 5 6\n"))
                         .scene;
  ASSERT_EQ(quad.surfaces.size(), 1u);
  EXPECT_EQ(quad.surfaces[0].points.size(), 4u);
  EXPECT_EQ(quad.surfaces[0].polygons, (std::vector<std::vector<int>>{{0, 1, 2}, {0, 2, 3}}));
}

TEST(SceneLoader, ZeroAreaFacesAreDroppedAndCounted) {
  const LoadResult loaded = load_scene(write("zero_area", "sliver.obj",
                                             "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 2 0 0\n"
                                             "f 1 2 3\n"
                                             "f 1 2 4\n"));  // collinear
  EXPECT_EQ(loaded.scene.dropped_zero_area_faces, 1);
  ASSERT_EQ(loaded.scene.surfaces.size(), 1u);
  EXPECT_NEAR(loaded.scene.surfaces[0].area, 0.5, 1e-12);
  ASSERT_EQ(loaded.warnings.size(), 1u);
  EXPECT_EQ(loaded.warnings[0], "dropped 1 zero-area faces");
}

TEST(SceneLoader, NegativeObjIndicesCountBackFromTheLastVertex) {
  const Scene scene =
      load_scene(write("negative", "tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -3 -2 -1\n")).scene;
  ASSERT_EQ(scene.surfaces.size(), 1u);
  EXPECT_NEAR(scene.surfaces[0].area, 0.5, 1e-12);
  EXPECT_NEAR(scene.surfaces[0].normal[2], 1.0, 1e-12);
}

// A unit square in z = 0 split into a left and a right half, 2 triangles each.
const char* const kSquarePoints = "0 0 0\n0.5 0 0\n1 0 0\n0 1 0\n0.5 1 0\n1 1 0\n";
const char* const kSquareFaces[] = {"3 0 1 4", "3 0 4 3", "3 1 2 5", "3 1 5 4"};

TEST(SceneLoader, PlyFaceColoursBecomeMaterials) {
  std::string ply =
      "ply\nformat ascii 1.0\ncomment two colours\nelement vertex 6\nproperty float x\nproperty float y\n"
      "property float z\nelement face 4\nproperty list uchar int vertex_indices\nproperty uchar red\n"
      "property uchar green\nproperty uchar blue\nend_header\n";
  ply += kSquarePoints;
  ply += std::string(kSquareFaces[0]) + " 255 0 0\n" + kSquareFaces[1] + " 255 0 0\n";
  ply += std::string(kSquareFaces[2]) + " 0 51 102\n" + kSquareFaces[3] + " 0 51 102\n";
  const Scene scene = load_scene(write("ply_colours", "square.ply", ply)).scene;
  ASSERT_EQ(scene.surfaces.size(), 2u);
  const Material& red = scene.materials.at(scene.surfaces[0].material);
  const Material& blue = scene.materials.at(scene.surfaces[1].material);
  // 8-bit white is reflectance 1, as Kd 1 in an MTL.
  EXPECT_EQ(red.reflectance[0], 1.0);
  EXPECT_EQ(red.reflectance[1], 0.0);
  EXPECT_NEAR(blue.reflectance[1], 0.2, 1e-12);
  EXPECT_NEAR(blue.reflectance[2], 0.4, 1e-12);
  EXPECT_FALSE(red.is_emitter());
  EXPECT_NEAR(scene.surfaces[0].area + scene.surfaces[1].area, 1.0, 1e-6);
}

TEST(SceneLoader, PlyVertexColoursAreAveragedPerFace) {
  std::string ply =
      "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
      "property uchar red\nproperty uchar green\nproperty uchar blue\n"
      "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
      "0 0 0 0 0 0\n1 0 0 100 0 0\n1 1 0 100 0 0\n0 1 0 0 0 0\n4 0 1 2 3\n";
  const Scene scene = load_scene(write("ply_vertex_colours", "quad.ply", ply)).scene;
  ASSERT_EQ(scene.surfaces.size(), 1u);
  EXPECT_EQ(scene.surfaces[0].polygons[0].size(), 4u);
  EXPECT_NEAR(scene.materials.at(scene.surfaces[0].material).reflectance[0], 50.0 / 255.0, 1e-12);
}

TEST(SceneLoader, BinaryPlyLoads) {
  std::string ply =
      "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
      "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
  const float points[9] = {0, 0, 0, 2, 0, 0, 0, 2, 0};
  ply.append(reinterpret_cast<const char*>(points), sizeof points);
  ply.push_back(3);
  const std::int32_t indices[3] = {0, 1, 2};
  ply.append(reinterpret_cast<const char*>(indices), sizeof indices);
  const Scene scene = load_scene(write("ply_binary", "tri.ply", ply)).scene;
  ASSERT_EQ(scene.surfaces.size(), 1u);
  EXPECT_NEAR(scene.surfaces[0].area, 2.0, 1e-12);
  EXPECT_EQ(scene.materials.at(scene.surfaces[0].material).reflectance, Rgb(0.5, 0.5, 0.5));
}

// Coordinates survive as stored: a double is not narrowed to float on the
// way (OpenMesh's own reader does that), and a float is widened exactly.
TEST(SceneLoader, PlyAndOffCoordinatesAreReadAsTheFileStoresThem) {
  const std::vector<Vec3> expected{{0.1, 0.2, 0.3}, {1.1, 0.2, 0.3}, {0.1, 1.7, 0.3}};
  const auto check = [&](const PolygonSoup& soup, bool as_float, const std::string& what) {
    ASSERT_EQ(soup.points.size(), 3u) << what;
    for (std::size_t v = 0; v < 3; ++v) {
      for (int k = 0; k < 3; ++k) {
        const double want = as_float ? static_cast<double>(static_cast<float>(expected[v][k])) : expected[v][k];
        EXPECT_EQ(soup.points[v][k], want) << what << " vertex " << v;
      }
    }
  };
  const std::string ascii_header =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty double x\nproperty double y\nproperty double z\n"
      "element face 1\nproperty list uchar int vertex_indices\nend_header\n";
  check(load_polygon_soup(write("coords_ascii_ply", "t.ply",
                                ascii_header + "0.1 0.2 0.3\n1.1 0.2 0.3\n0.1 1.7 0.3\n3 0 1 2\n")),
        false, "ASCII PLY");
  check(load_polygon_soup(write("coords_off", "t.off", "OFF\n3 1 0\n0.1 0.2 0.3\n1.1 0.2 0.3\n0.1 1.7 0.3\n3 0 1 2\n")),
        false, "ASCII OFF");
  for (const bool doubles : {true, false}) {
    const std::string type = doubles ? "double" : "float";
    std::string ply = "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty " + type +
                      " x\nproperty " + type + " y\nproperty " + type +
                      " z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
    for (const Vec3& p : expected) {
      for (int k = 0; k < 3; ++k) {
        if (doubles) {
          const double d = p[k];
          ply.append(reinterpret_cast<const char*>(&d), sizeof d);
        } else {
          const float f = static_cast<float>(p[k]);
          ply.append(reinterpret_cast<const char*>(&f), sizeof f);
        }
      }
    }
    ply.push_back(3);
    const std::int32_t indices[3] = {0, 1, 2};
    ply.append(reinterpret_cast<const char*>(indices), sizeof indices);
    check(load_polygon_soup(write("coords_binary_" + type, "t.ply", ply)), !doubles, "binary PLY of " + type);
  }
}

TEST(SceneLoader, BinaryOffLoads) {
  std::string off = "OFF BINARY\n";
  const std::int32_t counts[3] = {4, 1, 0};
  off.append(reinterpret_cast<const char*>(counts), sizeof counts);
  const float points[12] = {0, 0, 0, 3, 0, 0, 3, 1, 0, 0, 1, 0};
  off.append(reinterpret_cast<const char*>(points), sizeof points);
  const std::int32_t face[5] = {4, 0, 1, 2, 3};
  off.append(reinterpret_cast<const char*>(face), sizeof face);
  const Scene scene = load_scene(write("off_binary", "rect.off", off)).scene;
  ASSERT_EQ(scene.surfaces.size(), 1u);
  EXPECT_EQ(scene.surfaces[0].polygons[0].size(), 4u);
  EXPECT_NEAR(scene.surfaces[0].area, 3.0, 1e-12);
}

TEST(SceneLoader, OffFaceColoursBecomeMaterials) {
  std::string off = "OFF\n# a comment\n6 4 0\n";
  off += kSquarePoints;
  off += std::string(kSquareFaces[0]) + " 0 255 0\n" + kSquareFaces[1] + " 0 255 0\n";
  off += std::string(kSquareFaces[2]) + " 0.2 0.4 0.6\n" + kSquareFaces[3] + " 0.2 0.4 0.6\n";
  const Scene scene = load_scene(write("off_colours", "square.off", off)).scene;
  ASSERT_EQ(scene.surfaces.size(), 2u);
  const Material& green = scene.materials.at(scene.surfaces[0].material);
  const Material& other = scene.materials.at(scene.surfaces[1].material);
  EXPECT_EQ(green.reflectance[1], 1.0);
  EXPECT_EQ(green.reflectance[0], 0.0);
  EXPECT_NEAR(other.reflectance[0], 51.0 / 255.0, 1e-12);
  EXPECT_NEAR(other.reflectance[2], 153.0 / 255.0, 1e-12);
  EXPECT_EQ(scene.surfaces[0].name, "square/rgb_00ff00#0");
}

// Geomview's OFF: a vertex is x y z [normal] [colour] [s t] as the header's
// N, C and ST prefixes say; a colour has 3 or 4 components, integers in
// 0..255 or floats in 0..1. Two separate triangles, one colour each: the
// loader names a face's material after its colour's 8-bit value.
struct OffVariant {
  const char* name;
  const char* header;
  const char* extra_before;  // normal, between x y z and the colour
  const char* first;         // colour of the first triangle's vertices
  const char* second;
  const char* extra_after;   // texture coordinate
  const char* want_first;
  const char* want_second;
};

TEST(SceneLoader, EveryOffVertexColourTheSpecificationAllows) {
  const OffVariant variants[] = {
      {"rgb_bytes", "COFF", "", "255 128 0", "0 0 255", "", "rgb_ff8000", "rgb_0000ff"},
      {"rgba_bytes", "COFF", "", "255 128 0 255", "0 0 255 255", "", "rgb_ff8000", "rgb_0000ff"},
      // A float file whose first colour has no decimal point is still floats.
      {"rgb_floats", "COFF", "", "1 0 0", "0 0.2 1", "", "rgb_ff0000", "rgb_0033ff"},
      {"rgba_floats", "COFF", "", "1.0 0.5 0.0 1.0", "0.0 0.0 1.0 0.5", "", "rgb_ff8000", "rgb_0000ff"},
      {"normals", "CNOFF", "0 0 1 ", "0.2 0.4 0.6 1", "1 1 1 1", "", "rgb_336699", "rgb_ffffff"},
      {"texcoords", "STCNOFF", "0 0 1 ", "51 102 153", "0 0 0", " 0.5 0.5", "rgb_336699", "rgb_000000"},
      {"no_c_prefix", "OFF", "", "51 102 153", "0 0 0", "", "rgb_336699", "rgb_000000"},
  };
  const char* const points[6] = {"0 0 0", "1 0 0", "0 1 0", "0 0 1", "1 0 1", "0 1 1"};
  for (const OffVariant& v : variants) {
    SCOPED_TRACE(v.name);
    std::string off = std::string(v.header) + "\n6 2 0\n";
    for (int i = 0; i < 6; ++i) {
      off += std::string(points[i]) + " " + v.extra_before + (i < 3 ? v.first : v.second) + v.extra_after + "\n";
    }
    off += "3 0 1 2\n3 3 4 5\n";
    const PolygonSoup soup = load_polygon_soup(write(std::string("off_variant_") + v.name, "t.off", off));
    ASSERT_EQ(soup.faces.size(), 2u);
    EXPECT_EQ(soup.materials[soup.faces[0].material].name, v.want_first);
    EXPECT_EQ(soup.materials[soup.faces[1].material].name, v.want_second);
  }
}

TEST(SceneLoader, OffFaceColourForms) {
  // After a face's indices: RGBA bytes or floats, or a colour-map index
  // (no colour map is read: the face keeps its vertices' colour).
  const std::string off =
      "COFF\n6 3 0\n0 0 0 10 20 30\n1 0 0 10 20 30\n0 1 0 10 20 30\n0 0 1 10 20 30\n1 0 1 10 20 30\n"
      "0 1 1 10 20 30\n3 0 1 2 51 102 153 255\n3 3 4 5 0.2 0.4 0.6 0.5\n3 0 2 5 7\n";
  const PolygonSoup soup = load_polygon_soup(write("off_face_colours", "t.off", off));
  ASSERT_EQ(soup.faces.size(), 3u);
  EXPECT_EQ(soup.materials[soup.faces[0].material].name, "rgb_336699");
  EXPECT_EQ(soup.materials[soup.faces[1].material].name, "rgb_336699");
  EXPECT_EQ(soup.materials[soup.faces[2].material].name, "rgb_0a141e");
}

TEST(SceneLoader, PlainOffWithoutColoursIsGrey) {
  std::string off = "OFF\n6 4 0\n";
  off += kSquarePoints;
  for (const char* f : kSquareFaces) off += std::string(f) + "\n";
  const Scene scene = load_scene(write("off_plain", "square.off", off)).scene;
  ASSERT_EQ(scene.surfaces.size(), 1u);
  EXPECT_NEAR(scene.surfaces[0].area, 1.0, 1e-6);
  EXPECT_EQ(scene.materials.at(scene.surfaces[0].material).reflectance, Rgb(0.5, 0.5, 0.5));
}

TEST(SurfaceSplit, InconsistentlyOrientedNeighboursAreSeparate) {
  // Two coplanar triangles sharing an edge, the second one flipped: their
  // front sides differ by 180°, so they cannot share radiance.
  PolygonSoup soup;
  soup.points = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  soup.materials = {Material{}};
  soup.groups = {"g"};
  soup.faces = {{{0, 1, 2}, 0, 0, 1}, {{0, 3, 2}, 0, 0, 2}};
  const SurfaceSplit split = split_into_surfaces(soup, 30.0);
  ASSERT_EQ(split.surfaces.size(), 2u);
  EXPECT_NEAR(split.surfaces[0].normal[2], 1.0, 1e-12);
  EXPECT_NEAR(split.surfaces[1].normal[2], -1.0, 1e-12);
  EXPECT_EQ(split_into_surfaces(soup, 180.0).surfaces.size(), 1u);
}

TEST(SurfaceSplit, EachSurfaceRecordsTheEdgesItSharesWithAnother) {
  // Three triangles of a square strip: the first two share material 0, the
  // third has material 1. Only the edge between the second and the third is
  // a seam, recorded in both surfaces with their own point indices.
  PolygonSoup soup;
  soup.points = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {2, 0, 0}};
  soup.materials = {Material{}, Material{}};
  soup.groups = {"g"};
  soup.faces = {{{0, 1, 2}, 0, 0, 1}, {{0, 2, 3}, 0, 0, 2}, {{1, 4, 2}, 1, 0, 3}};
  const SurfaceSplit split = split_into_surfaces(soup, 30.0);
  ASSERT_EQ(split.surfaces.size(), 2u);
  for (const Surface& s : split.surfaces) {
    ASSERT_EQ(s.seam_edges.size(), 1u) << s.name;
    const Vec3 a = s.points[s.seam_edges[0].first], b = s.points[s.seam_edges[0].second];
    EXPECT_EQ(std::min(a[1], b[1]), 0.0);
    EXPECT_EQ(std::max(a[1], b[1]), 1.0);
    EXPECT_EQ(a[0], 1.0);
    EXPECT_EQ(b[0], 1.0);
  }
}

TEST(SurfaceSplit, SlightlyBentSurfaceIsNotPlanar) {
  // Two triangles folded by 2° along their shared edge: one surface at the
  // default crease angle, but not planar.
  const double bend = 2.0 * M_PI / 180.0;
  PolygonSoup soup;
  soup.points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {-std::cos(bend), 0, std::sin(bend)}};
  soup.materials = {Material{}};
  soup.groups = {"g"};
  soup.faces = {{{0, 1, 2}, 0, 0, 1}, {{0, 2, 3}, 0, 0, 2}};
  const SurfaceSplit split = split_into_surfaces(soup, 30.0);
  ASSERT_EQ(split.surfaces.size(), 1u);
  EXPECT_FALSE(split.surfaces[0].planar);
  EXPECT_EQ(split_into_surfaces(soup, 1.0).surfaces.size(), 2u);
}

// ---------------------------------------------------------------------------
// Materials from the wild: Kd 1, textures, ignored keys, file names with
// spaces, byte-order marks.

const char* const kLitQuads =
    "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\nv 2 1 0\n"
    "o a\nusemtl a\nf 1 2 3 4\no b\nusemtl b\nf 2 5 6 3\n";

std::vector<std::string> matching(const std::vector<std::string>& warnings, const std::string& fragment) {
  std::vector<std::string> out;
  for (const std::string& w : warnings) {
    if (w.find(fragment) != std::string::npos) out.push_back(w);
  }
  return out;
}

TEST(SceneLoader, KdOneIsAcceptedWithOneWarningNamingTheMaterials) {
  const auto dir = fresh_dir("kd_one");
  write_text(dir / "m.mtl", "newmtl a\nKd 1 1 1\nnewmtl b\nKd 0.5 1.0 0.5\n");
  write_text(dir / "m.obj", std::string("mtllib m.mtl\n") + kLitQuads);
  const LoadResult loaded = load_scene(dir / "m.obj");
  ASSERT_EQ(loaded.scene.surfaces.size(), 2u);
  EXPECT_EQ(loaded.scene.materials.at(loaded.scene.surfaces[0].material).reflectance, Rgb(1, 1, 1));
  EXPECT_EQ(loaded.scene.materials.at(loaded.scene.surfaces[1].material).reflectance, Rgb(0.5, 1, 0.5));
  const auto white = matching(loaded.warnings, "reflectance 1");
  ASSERT_EQ(white.size(), 1u) << ::testing::PrintToString(loaded.warnings);
  EXPECT_NE(white[0].find("'a', 'b'"), std::string::npos) << white[0];
  EXPECT_EQ(white[0].find('\n'), std::string::npos);
}

TEST(SceneLoader, PlyWhiteIsReflectanceOneWithTheSameWarning) {
  std::string ply =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
      "property uchar red\nproperty uchar green\nproperty uchar blue\n"
      "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
      "0 0 0 255 255 255\n1 0 0 255 255 255\n0 1 0 255 255 255\n3 0 1 2\n";
  const LoadResult loaded = load_scene(write("ply_white", "w.ply", ply));
  EXPECT_EQ(loaded.scene.materials.at(loaded.scene.surfaces[0].material).reflectance, Rgb(1, 1, 1));
  const auto white = matching(loaded.warnings, "reflectance 1");
  ASSERT_EQ(white.size(), 1u) << ::testing::PrintToString(loaded.warnings);
  EXPECT_NE(white[0].find("'rgb_ffffff'"), std::string::npos) << white[0];
}

TEST(SceneLoader, TextureWithoutKdGivesTheTexturesMeanColour) {
  const auto dir = fresh_dir("map_kd");
  // An 8-bit PNG is sRGB-encoded: 0 and 1 decode to 0 and 1, so the mean of
  // red, blue, white and black is (0.5, 0.25, 0.5) exactly.
  Image png(2, 2);
  const float pixels[4][3] = {{1, 0, 0}, {0, 0, 1}, {1, 1, 1}, {0, 0, 0}};
  for (int i = 0; i < 4; ++i) std::copy(pixels[i], pixels[i] + 3, png.pixel(i % 2, i / 2));
  write_image(dir / "wood grain.png", png);
  // An EXR is linear: 0.25 and 0.75 (exact in half floats) average to 0.5.
  Image exr(2, 1);
  std::fill(exr.pixel(0, 0), exr.pixel(0, 0) + 3, 0.25f);
  std::fill(exr.pixel(1, 0), exr.pixel(1, 0) + 3, 0.75f);
  write_image(dir / "grey.exr", exr);
  write_text(dir / "m.mtl",
             "newmtl a\nmap_Kd -s 1 1 1 wood grain.png\n"
             "newmtl b\nmap_Kd grey.exr\n");
  write_text(dir / "m.obj", std::string("mtllib m.mtl\n") + kLitQuads);
  const LoadResult loaded = load_scene(dir / "m.obj");
  const Scene& scene = loaded.scene;
  ASSERT_EQ(scene.surfaces.size(), 2u);
  const Rgb a = scene.materials.at(scene.surfaces[0].material).reflectance;
  const Rgb b = scene.materials.at(scene.surfaces[1].material).reflectance;
  EXPECT_LT((a - Rgb(0.5, 0.25, 0.5)).norm(), 1e-6) << a;
  EXPECT_LT((b - Rgb(0.5, 0.5, 0.5)).norm(), 1e-6) << b;
  EXPECT_TRUE(loaded.warnings.empty()) << ::testing::PrintToString(loaded.warnings);
}

TEST(SceneLoader, MissingTextureWithoutKdIsGreyWithAWarning) {
  const auto dir = fresh_dir("map_kd_missing");
  write_text(dir / "m.mtl", "newmtl a\nmap_Kd gone.png\nnewmtl b\nKd 0.2 0.2 0.2\nmap_Kd gone.png\n");
  write_text(dir / "m.obj", std::string("mtllib m.mtl\n") + kLitQuads);
  const LoadResult loaded = load_scene(dir / "m.obj");
  const Scene& scene = loaded.scene;
  EXPECT_EQ(scene.materials.at(scene.surfaces[0].material).reflectance, Rgb(0.5, 0.5, 0.5));
  // Kd wins over a texture, missing or not.
  EXPECT_LT((scene.materials.at(scene.surfaces[1].material).reflectance - Rgb(0.2, 0.2, 0.2)).norm(), 1e-12);
  ASSERT_EQ(loaded.warnings.size(), 1u) << ::testing::PrintToString(loaded.warnings);
  EXPECT_NE(loaded.warnings[0].find("m.mtl:1"), std::string::npos) << loaded.warnings[0];
  EXPECT_NE(loaded.warnings[0].find("gone.png"), std::string::npos) << loaded.warnings[0];
  EXPECT_NE(loaded.warnings[0].find("grey 0.5"), std::string::npos) << loaded.warnings[0];
}

TEST(SceneLoader, IgnoredMtlKeysAreSummarisedInOneWarning) {
  const auto dir = fresh_dir("mtl_ignored");
  // What Blender's OBJ exporter writes for a Principled BSDF.
  write_text(dir / "m.mtl",
             "# Blender MTL File\nnewmtl a\nNs 250.0\nKa 1.0 1.0 1.0\nKd 0.8 0.8 0.8\nKs 0.5 0.5 0.5\n"
             "Ke 0.0 0.0 0.0\nNi 1.45\nd 1.0\nillum 2\n\nnewmtl b\nNs 10\nKd 0.1 0.1 0.1\nillum 2\n");
  write_text(dir / "m.obj", std::string("mtllib m.mtl\n") + kLitQuads);
  const LoadResult loaded = load_scene(dir / "m.obj");
  ASSERT_EQ(loaded.warnings.size(), 1u) << ::testing::PrintToString(loaded.warnings);
  EXPECT_NE(loaded.warnings[0].find("Ns, Ka, Ks, Ni, d, illum"), std::string::npos) << loaded.warnings[0];
  EXPECT_NE(loaded.warnings[0].find("m.mtl"), std::string::npos) << loaded.warnings[0];
  EXPECT_LT((loaded.scene.materials.at(loaded.scene.surfaces[0].material).reflectance - Rgb(0.8, 0.8, 0.8)).norm(),
            1e-12);
}

TEST(SceneLoader, MtllibNamesWithSpacesAndSeveralOnOneLine) {
  const auto dir = fresh_dir("mtllib_spaces");
  write_text(dir / "my room.mtl", "newmtl a\nKd 0.25 0.5 0.75\n");
  write_text(dir / "first.mtl", "newmtl a\nKd 0.25 0.5 0.75\n");
  write_text(dir / "second.mtl", "newmtl b\nKd 0.1 0.2 0.3\n");
  write_text(dir / "spaces.obj", std::string("mtllib my room.mtl\nmtllib second.mtl\n") + kLitQuads);
  write_text(dir / "two.obj", std::string("mtllib first.mtl second.mtl\n") + kLitQuads);
  for (const char* name : {"spaces.obj", "two.obj"}) {
    SCOPED_TRACE(name);
    const Scene scene = load_scene(dir / name).scene;
    ASSERT_EQ(scene.surfaces.size(), 2u);
    EXPECT_LT((scene.materials.at(scene.surfaces[0].material).reflectance - Rgb(0.25, 0.5, 0.75)).norm(), 1e-12);
    EXPECT_LT((scene.materials.at(scene.surfaces[1].material).reflectance - Rgb(0.1, 0.2, 0.3)).norm(), 1e-12);
  }
}

TEST(SceneLoader, ByteOrderMarksAreSkipped) {
  const auto dir = fresh_dir("bom");
  const std::string bom = "\xEF\xBB\xBF";
  write_text(dir / "m.mtl", bom + "newmtl a\nKd 0.25 0.5 0.75\nnewmtl b\nKd 0.1 0.2 0.3\n");
  write_text(dir / "n.obj", bom + std::string("mtllib m.mtl\n") + kLitQuads);
  const Scene scene = load_scene(dir / "n.obj").scene;
  ASSERT_EQ(scene.surfaces.size(), 2u);
  EXPECT_LT((scene.materials.at(scene.surfaces[0].material).reflectance - Rgb(0.25, 0.5, 0.75)).norm(), 1e-12);
  EXPECT_LT((scene.materials.at(scene.surfaces[1].material).reflectance - Rgb(0.1, 0.2, 0.3)).norm(), 1e-12);
  // Here the BOM sits before the first vertex, which would otherwise be lost.
  write_text(dir / "plain.obj", bom + std::string("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"));
  const PolygonSoup soup = load_polygon_soup(dir / "plain.obj");
  ASSERT_EQ(soup.points.size(), 3u);
  EXPECT_EQ(soup.points[0], Vec3(0, 0, 0));
}

}  // namespace
}  // namespace lhr
