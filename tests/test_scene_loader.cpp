// Scene loading (docs/design.md §3): what load_scene makes of bare geometry
// and of a scene JSON: surfaces cut at creases, welded vertices, dropped
// zero-area faces, the camera and the meshing settings. The readers of each
// format have their own tests (test_obj_reader, test_ply_off_reader).

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "io/scene_loader.hpp"
#include "mesh/surfaces.hpp"
#include "scene_fixtures.hpp"
#include "test_support.hpp"

namespace lhr {
namespace {

using test::fresh_dir;
using test::fresh_file;
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

TEST(SceneLoader, OneMaterialBoxOfQuadsIsSixPlanarUnitSurfaces) {
  const Scene scene = load_scene(fresh_file("box_quads", "box.obj", cube_as_quads())).scene;
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
  const Scene scene = load_scene(fresh_file("box_tris", "box.obj", cube_as_triangles())).scene;
  ASSERT_EQ(scene.surfaces.size(), 6u);
  for (const Surface& s : scene.surfaces) {
    EXPECT_EQ(s.polygons.size(), 2u);
    EXPECT_EQ(s.points.size(), 4u);
    EXPECT_TRUE(s.planar);
    EXPECT_NEAR(s.area, 1.0, 1e-12);
  }
}

TEST(SceneLoader, TessellatedSphereIsOneCurvedSurface) {
  const auto path = fresh_file("sphere", "sphere.obj", icosphere(2, false));
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
  const auto path = fresh_file("sphere_crease", "sphere.obj", icosphere(2, false));
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
  const auto box = fresh_file("box_crease", "box.obj", cube_as_quads());
  options.crease_angle_deg = 89.0;
  EXPECT_EQ(load_scene(box, options).scene.surfaces.size(), 6u);
  options.crease_angle_deg = 91.0;
  EXPECT_EQ(load_scene(box, options).scene.surfaces.size(), 1u);
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
  const Scene scene = load_scene(fresh_file("framing", "box.obj", cube_as_quads())).scene;
  ASSERT_TRUE(scene.camera.has_value());
  const Camera expected = framing_camera(scene);
  EXPECT_EQ(scene.camera->eye, expected.eye);
  EXPECT_EQ(scene.camera->target, Vec3(0.5, 0.5, 0.5));
}

TEST(SceneLoader, DuplicatedPositionVerticesAreWelded) {
  // Every triangle of the sphere has its own three vertices, as many
  // exporters write them; it must still be one surface with shared points.
  const Scene scene = load_scene(fresh_file("welded_sphere", "sphere.obj", icosphere(1, true))).scene;
  ASSERT_EQ(scene.surfaces.size(), 1u);
  EXPECT_EQ(scene.surfaces[0].polygons.size(), 80u);
  EXPECT_EQ(scene.surfaces[0].points.size(), 42u);  // V = E - F + 2 = 120 - 80 + 2

  // A quad written as two triangles with six distinct vertices.
  const Scene quad = load_scene(fresh_file("welded_quad", "quad.obj",
                                           "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 0 0\nv 1 1 0\nv 0 1 0\n"
                                           "f 1 2 3\nf 4 5 6\n"))
                         .scene;
  ASSERT_EQ(quad.surfaces.size(), 1u);
  EXPECT_EQ(quad.surfaces[0].points.size(), 4u);
  EXPECT_EQ(quad.surfaces[0].polygons, (std::vector<std::vector<int>>{{0, 1, 2}, {0, 2, 3}}));
}

TEST(SceneLoader, ZeroAreaFacesAreDroppedAndCounted) {
  const LoadResult loaded = load_scene(fresh_file("zero_area", "sliver.obj",
                                                  "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 2 0 0\n"
                                                  "f 1 2 3\n"
                                                  "f 1 2 4\n"));  // collinear
  EXPECT_EQ(loaded.scene.dropped_zero_area_faces, 1);
  ASSERT_EQ(loaded.scene.surfaces.size(), 1u);
  EXPECT_NEAR(loaded.scene.surfaces[0].area, 0.5, 1e-12);
  ASSERT_EQ(loaded.warnings.size(), 1u);
  EXPECT_EQ(loaded.warnings[0], "dropped 1 zero-area faces");
}

// A grid of n x n vertices in y = 0, two triangles per cell, facing +y, as
// each text format writes it (binary PLY beside): big enough that the
// readers and the split pass their checkpoint many times.
struct GridFiles {
  int vertices = 0, faces = 0;
  std::map<std::string, std::string> by_name;
};

GridFiles grid_files(int n) {
  GridFiles g;
  g.vertices = n * n;
  g.faces = 2 * (n - 1) * (n - 1);
  std::string points, obj_points, tris, obj_tris, off_tris;
  std::string binary_points, binary_tris;
  const auto append_bytes = [](std::string& out, const auto& value) {
    out.append(reinterpret_cast<const char*>(&value), sizeof value);
  };
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      const std::string xyz = std::to_string(i) + " 0 " + std::to_string(j);
      points += xyz + "\n";
      obj_points += "v " + xyz + "\n";
      for (const float c : {static_cast<float>(i), 0.0f, static_cast<float>(j)}) append_bytes(binary_points, c);
    }
  }
  for (int j = 0; j + 1 < n; ++j) {
    for (int i = 0; i + 1 < n; ++i) {
      const int a = j * n + i, b = a + 1, c = a + n, d = c + 1;
      for (const std::array<int, 3>& t : {std::array<int, 3>{a, c, d}, std::array<int, 3>{a, d, b}}) {
        const std::string idx = std::to_string(t[0]) + " " + std::to_string(t[1]) + " " + std::to_string(t[2]);
        tris += "3 " + idx + "\n";
        obj_tris += "f " + std::to_string(t[0] + 1) + " " + std::to_string(t[1] + 1) + " " +
                    std::to_string(t[2] + 1) + "\n";
        binary_tris.push_back(3);
        for (const std::int32_t v : t) append_bytes(binary_tris, v);
      }
    }
  }
  const std::string header = "element vertex " + std::to_string(g.vertices) +
                             "\nproperty float x\nproperty float y\nproperty float z\nelement face " +
                             std::to_string(g.faces) + "\nproperty list uchar int vertex_indices\nend_header\n";
  g.by_name["grid.obj"] = obj_points + obj_tris;
  g.by_name["grid.ply"] = "ply\nformat ascii 1.0\n" + header + points + tris;
  g.by_name["grid_binary.ply"] = "ply\nformat binary_little_endian 1.0\n" + header + binary_points + binary_tris;
  g.by_name["grid.off"] = "OFF\n" + std::to_string(g.vertices) + " " + std::to_string(g.faces) + " 0\n" + points + tris;
  return g;
}

// A signal must not wait for the whole of a large file's read, parse and
// split (docs/robustness.md, "Interrupted runs"): every reader calls the
// checkpoint every few thousand lines or elements, the split every few
// thousand faces and edges, and what the checkpoint throws ends the load
// as it was thrown.
TEST(SceneLoader, EveryFormatCallsTheCheckpointAsItLoadsAndWhatItThrowsEndsTheLoad) {
  constexpr int kSide = 120;
  const GridFiles grid = grid_files(kSide);
  // What the split calls on the same grid as a soup.
  int split_calls = 0;
  ASSERT_EQ(split_into_surfaces(test::grid_soup(kSide), 30.0, [&] { ++split_calls; }).surfaces.size(), 1u);
  struct Stop {};
  for (const auto& [name, text] : grid.by_name) {
    SCOPED_TRACE(name);
    const auto path = fresh_file("loader_checkpoint", name, text);
    LoadOptions options;
    int calls = 0;
    options.checkpoint = [&] { ++calls; };
    const LoadResult loaded = load_scene(path, options);
    ASSERT_EQ(loaded.scene.surfaces.size(), 1u);
    // The reader's own calls: at least one per 4 096 of the vertex and
    // face lines or elements it parses, beside the split's.
    EXPECT_GE(calls - split_calls, (grid.vertices + grid.faces) / 4096);
    for (const int stop_at : {1, 3, calls / 2, calls}) {
      int seen = 0;
      options.checkpoint = [&] {
        if (++seen == stop_at) throw Stop{};
      };
      EXPECT_THROW(load_scene(path, options), Stop) << "stopped at call " << stop_at;
      EXPECT_EQ(seen, stop_at) << "nothing ran the checkpoint after it threw";
    }
  }
}

}  // namespace
}  // namespace lhr
