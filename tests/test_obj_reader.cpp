// OBJ and MTL loading (docs/design.md §3): groups, materials and polygons as
// written, and the MTL files other tools write (Kd 1, textures, keys lhr
// ignores, file names with spaces, byte-order marks).

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include "io/image_io.hpp"
#include "io/scene_loader.hpp"
#include "test_support.hpp"

namespace lhr {
namespace {

using test::containing;
using test::fresh_dir;
using test::fresh_file;
using test::write_text;

// How far apart two colours are: the largest difference over the channels.
double max_difference(const Rgb& a, const Rgb& b) {
  return std::max({std::abs(a[0] - b[0]), std::abs(a[1] - b[1]), std::abs(a[2] - b[2])});
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
  EXPECT_LT(max_difference(white.reflectance, Rgb(0.8, 0.7, 0.6)), 1e-12);
  EXPECT_FALSE(white.is_emitter());
  EXPECT_LT(max_difference(lamp.reflectance, Rgb(0.1, 0.2, 0.3)), 1e-12);
  EXPECT_LT(max_difference(lamp.emission, Rgb(10, 20, 30)), 1e-12);
  EXPECT_TRUE(lamp.is_emitter());

  // The same faces in one group with one material form one surface.
  write_text(dir / "one.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\nv 2 1 0\nf 1 2 3 4\nf 2 5 6 3\n");
  const Scene one = load_scene(dir / "one.obj").scene;
  ASSERT_EQ(one.surfaces.size(), 1u);
  EXPECT_EQ(one.surfaces[0].points.size(), 6u);
  EXPECT_NEAR(one.surfaces[0].area, 2.0, 1e-12);
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
  const Scene scene = load_scene(fresh_file("ngons", "ngons.obj", obj.str())).scene;
  ASSERT_EQ(scene.surfaces.size(), 2u);
  ASSERT_EQ(scene.surfaces[0].polygons.size(), 1u);
  EXPECT_EQ(scene.surfaces[0].polygons[0], (std::vector<int>{0, 1, 2, 3, 4}));
  EXPECT_EQ(scene.surfaces[1].polygons[0].size(), 6u);
  EXPECT_NEAR(scene.surfaces[0].area, 2.5 * std::sin(2 * M_PI / 5), 1e-12);
  EXPECT_NEAR(scene.surfaces[1].area, 3.0 * std::sin(2 * M_PI / 6), 1e-12);
  EXPECT_NEAR(scene.surfaces[0].normal[2], 1.0, 1e-12);
  EXPECT_TRUE(scene.surfaces[0].planar);
}

TEST(SceneLoader, NegativeObjIndicesCountBackFromTheLastVertex) {
  const Scene scene = load_scene(fresh_file("negative", "tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -3 -2 -1\n")).scene;
  ASSERT_EQ(scene.surfaces.size(), 1u);
  EXPECT_NEAR(scene.surfaces[0].area, 0.5, 1e-12);
  EXPECT_NEAR(scene.surfaces[0].normal[2], 1.0, 1e-12);
}

// ---------------------------------------------------------------------------
// Materials from the wild: Kd 1, textures, ignored keys, file names with
// spaces, byte-order marks.

const char* const kLitQuads =
    "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\nv 2 1 0\n"
    "o a\nusemtl a\nf 1 2 3 4\no b\nusemtl b\nf 2 5 6 3\n";

TEST(SceneLoader, KdOneIsAcceptedWithOneWarningNamingTheMaterials) {
  const auto dir = fresh_dir("kd_one");
  write_text(dir / "m.mtl", "newmtl a\nKd 1 1 1\nnewmtl b\nKd 0.5 1.0 0.5\n");
  write_text(dir / "m.obj", std::string("mtllib m.mtl\n") + kLitQuads);
  const LoadResult loaded = load_scene(dir / "m.obj");
  ASSERT_EQ(loaded.scene.surfaces.size(), 2u);
  EXPECT_EQ(loaded.scene.materials.at(loaded.scene.surfaces[0].material).reflectance, Rgb(1, 1, 1));
  EXPECT_EQ(loaded.scene.materials.at(loaded.scene.surfaces[1].material).reflectance, Rgb(0.5, 1, 0.5));
  const auto white = containing(loaded.warnings, "reflectance 1");
  ASSERT_EQ(white.size(), 1u) << ::testing::PrintToString(loaded.warnings);
  EXPECT_NE(white[0].find("'a', 'b'"), std::string::npos) << white[0];
  EXPECT_EQ(white[0].find('\n'), std::string::npos);
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
  EXPECT_LT(max_difference(a, Rgb(0.5, 0.25, 0.5)), 1e-6) << a;
  EXPECT_LT(max_difference(b, Rgb(0.5, 0.5, 0.5)), 1e-6) << b;
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
  EXPECT_LT(max_difference(scene.materials.at(scene.surfaces[1].material).reflectance, Rgb(0.2, 0.2, 0.2)), 1e-12);
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
  EXPECT_LT(
      max_difference(loaded.scene.materials.at(loaded.scene.surfaces[0].material).reflectance, Rgb(0.8, 0.8, 0.8)),
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
    EXPECT_LT(max_difference(scene.materials.at(scene.surfaces[0].material).reflectance, Rgb(0.25, 0.5, 0.75)), 1e-12);
    EXPECT_LT(max_difference(scene.materials.at(scene.surfaces[1].material).reflectance, Rgb(0.1, 0.2, 0.3)), 1e-12);
  }
}

TEST(SceneLoader, ByteOrderMarksAreSkipped) {
  const auto dir = fresh_dir("bom");
  const std::string bom = "\xEF\xBB\xBF";
  write_text(dir / "m.mtl", bom + "newmtl a\nKd 0.25 0.5 0.75\nnewmtl b\nKd 0.1 0.2 0.3\n");
  write_text(dir / "n.obj", bom + std::string("mtllib m.mtl\n") + kLitQuads);
  const Scene scene = load_scene(dir / "n.obj").scene;
  ASSERT_EQ(scene.surfaces.size(), 2u);
  EXPECT_LT(max_difference(scene.materials.at(scene.surfaces[0].material).reflectance, Rgb(0.25, 0.5, 0.75)), 1e-12);
  EXPECT_LT(max_difference(scene.materials.at(scene.surfaces[1].material).reflectance, Rgb(0.1, 0.2, 0.3)), 1e-12);
  // Here the BOM sits before the first vertex, which would otherwise be lost.
  write_text(dir / "plain.obj", bom + std::string("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"));
  const PolygonSoup soup = load_polygon_soup(dir / "plain.obj");
  ASSERT_EQ(soup.points.size(), 3u);
  EXPECT_EQ(soup.points[0], Vec3(0, 0, 0));
}

}  // namespace
}  // namespace lhr
