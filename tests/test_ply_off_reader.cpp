// PLY and OFF loading (docs/design.md §3): face and vertex colours become
// materials, ASCII and binary files, coordinates kept as the file stores
// them, and every colour form Geomview's OFF allows.

#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

#include "io/scene_loader.hpp"
#include "test_support.hpp"

namespace lhr {
namespace {

using test::containing;
using test::fresh_file;

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
  const Scene scene = load_scene(fresh_file("ply_colours", "square.ply", ply)).scene;
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
  const Scene scene = load_scene(fresh_file("ply_vertex_colours", "quad.ply", ply)).scene;
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
  const Scene scene = load_scene(fresh_file("ply_binary", "tri.ply", ply)).scene;
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
  check(load_polygon_soup(
            fresh_file("coords_ascii_ply", "t.ply", ascii_header + "0.1 0.2 0.3\n1.1 0.2 0.3\n0.1 1.7 0.3\n3 0 1 2\n")),
        false, "ASCII PLY");
  check(load_polygon_soup(
            fresh_file("coords_off", "t.off", "OFF\n3 1 0\n0.1 0.2 0.3\n1.1 0.2 0.3\n0.1 1.7 0.3\n3 0 1 2\n")),
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
    check(load_polygon_soup(fresh_file("coords_binary_" + type, "t.ply", ply)), !doubles, "binary PLY of " + type);
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
  const Scene scene = load_scene(fresh_file("off_binary", "rect.off", off)).scene;
  ASSERT_EQ(scene.surfaces.size(), 1u);
  EXPECT_EQ(scene.surfaces[0].polygons[0].size(), 4u);
  EXPECT_NEAR(scene.surfaces[0].area, 3.0, 1e-12);
}

TEST(SceneLoader, OffFaceColoursBecomeMaterials) {
  std::string off = "OFF\n# a comment\n6 4 0\n";
  off += kSquarePoints;
  off += std::string(kSquareFaces[0]) + " 0 255 0\n" + kSquareFaces[1] + " 0 255 0\n";
  off += std::string(kSquareFaces[2]) + " 0.2 0.4 0.6\n" + kSquareFaces[3] + " 0.2 0.4 0.6\n";
  const Scene scene = load_scene(fresh_file("off_colours", "square.off", off)).scene;
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
    const PolygonSoup soup = load_polygon_soup(fresh_file(std::string("off_variant_") + v.name, "t.off", off));
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
  const PolygonSoup soup = load_polygon_soup(fresh_file("off_face_colours", "t.off", off));
  ASSERT_EQ(soup.faces.size(), 3u);
  EXPECT_EQ(soup.materials[soup.faces[0].material].name, "rgb_336699");
  EXPECT_EQ(soup.materials[soup.faces[1].material].name, "rgb_336699");
  EXPECT_EQ(soup.materials[soup.faces[2].material].name, "rgb_0a141e");
}

TEST(SceneLoader, PlainOffWithoutColoursIsGrey) {
  std::string off = "OFF\n6 4 0\n";
  off += kSquarePoints;
  for (const char* f : kSquareFaces) off += std::string(f) + "\n";
  const Scene scene = load_scene(fresh_file("off_plain", "square.off", off)).scene;
  ASSERT_EQ(scene.surfaces.size(), 1u);
  EXPECT_NEAR(scene.surfaces[0].area, 1.0, 1e-6);
  EXPECT_EQ(scene.materials.at(scene.surfaces[0].material).reflectance, Rgb(0.5, 0.5, 0.5));
}

// The warning SceneLoader.KdOneIsAcceptedWithOneWarningNamingTheMaterials
// checks for an MTL's Kd 1 (test_obj_reader).
TEST(SceneLoader, PlyWhiteIsReflectanceOneWithTheSameWarning) {
  std::string ply =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
      "property uchar red\nproperty uchar green\nproperty uchar blue\n"
      "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
      "0 0 0 255 255 255\n1 0 0 255 255 255\n0 1 0 255 255 255\n3 0 1 2\n";
  const LoadResult loaded = load_scene(fresh_file("ply_white", "w.ply", ply));
  EXPECT_EQ(loaded.scene.materials.at(loaded.scene.surfaces[0].material).reflectance, Rgb(1, 1, 1));
  const auto white = containing(loaded.warnings, "reflectance 1");
  ASSERT_EQ(white.size(), 1u) << ::testing::PrintToString(loaded.warnings);
  EXPECT_NE(white[0].find("'rgb_ffffff'"), std::string::npos) << white[0];
}

}  // namespace
}  // namespace lhr
