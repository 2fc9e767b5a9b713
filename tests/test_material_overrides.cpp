// Materials given by a scene file (docs/scene-format.md, "materials"), and
// scenes of several geometry files: what a PLY/OFF scene needs to be lit.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "io/scene_loader.hpp"
#include "render/solution.hpp"
#include "test_support.hpp"

namespace lhr {
namespace {

using test::fresh_dir;
using test::write_text;

// An ASCII PLY of one quad with a face colour (8-bit).
std::string quad_ply(const std::array<Vec3, 4>& corners, int r, int g, int b) {
  std::string ply =
      "ply\nformat ascii 1.0\nelement vertex 4\nproperty double x\nproperty double y\nproperty double z\n"
      "element face 1\nproperty list uchar int vertex_indices\nproperty uchar red\nproperty uchar green\n"
      "property uchar blue\nend_header\n";
  for (const Vec3& p : corners) {
    ply += std::to_string(p[0]) + " " + std::to_string(p[1]) + " " + std::to_string(p[2]) + "\n";
  }
  ply += "4 0 1 2 3 " + std::to_string(r) + " " + std::to_string(g) + " " + std::to_string(b) + "\n";
  return ply;
}

// The geometry of test::write_lit_floor_obj as two PLY files, both grey.
void write_lit_floor_plys(const std::filesystem::path& dir) {
  write_text(dir / "floor.ply", quad_ply({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0)}, 128, 128, 128));
  write_text(dir / "light.ply",
             quad_ply({Vec3(0.2, 0.2, 0.5), Vec3(0.2, 0.8, 0.5), Vec3(0.8, 0.8, 0.5), Vec3(0.8, 0.2, 0.5)}, 128,
                      128, 128));
}

const Material& material_of(const Scene& scene, const std::string& surface_prefix) {
  for (const Surface& s : scene.surfaces) {
    if (s.name.rfind(surface_prefix, 0) == 0) return scene.materials.at(s.material);
  }
  ADD_FAILURE() << "no surface named " << surface_prefix << "...";
  return scene.materials.at(0);
}

std::string load_error(const std::filesystem::path& scene) {
  try {
    load_scene(scene);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(MaterialOverrides, PlyFilesLitByTheSceneFileSolveAsTheSameObjLitByItsMtl) {
  const auto dir = fresh_dir("override_ply_vs_obj");
  test::write_lit_floor_obj(dir);
  write_lit_floor_plys(dir);
  write_text(dir / "plys.scene.json",
             R"({"mesh": ["floor.ply", "light.ply"],
                 "materials": [{"file": "floor.ply", "reflectance": [0.7, 0.6, 0.5]},
                               {"file": "light.ply", "reflectance": 0, "emission": [3, 3, 3]}]})");
  const LoadResult plys = load_scene(dir / "plys.scene.json");
  const LoadResult obj = load_scene(dir / "tiny.obj");
  ASSERT_EQ(plys.scene.surfaces.size(), 2u);
  ASSERT_EQ(obj.scene.surfaces.size(), 2u);
  const Material& light = material_of(plys.scene, "light/");
  EXPECT_EQ(light.emission, Rgb(3, 3, 3));
  EXPECT_EQ(light.reflectance, Rgb(0, 0, 0));
  EXPECT_EQ(material_of(plys.scene, "floor/").reflectance, Rgb(0.7, 0.6, 0.5));
  EXPECT_FALSE(material_of(plys.scene, "floor/").is_emitter());

  // Same geometry and materials, so the same solution at every vertex: the
  // OBJ path is the one the closed-form tests check.
  SolveSettings settings;
  settings.meshing.max_edge = 0.25;
  settings.camera = framing_camera(obj.scene);
  const ExportMesh a = solve_scene(obj.scene, settings).view.export_mesh;
  const ExportMesh b = solve_scene(plys.scene, settings).view.export_mesh;
  ASSERT_EQ(a.points.size(), b.points.size());
  double floor_sum = 0.0;
  for (std::size_t v = 0; v < a.points.size(); ++v) {
    ASSERT_EQ(a.points[v], b.points[v]) << "vertex " << v;
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(b.radiance[v][k], a.radiance[v][k], 1e-9 * (1 + a.radiance[v][k]));
    if (a.points[v][2] == 0.0) floor_sum += b.radiance[v][0];
  }
  EXPECT_GT(floor_sum, 0.0) << "the floor is lit";
}

TEST(MaterialOverrides, AGroupSelectorSplitsAMaterialItSharesWithOtherGroups) {
  const auto dir = fresh_dir("override_group");
  write_text(dir / "m.mtl", "newmtl white\nKd 0.8 0.8 0.8\n");
  write_text(dir / "m.obj",
             "mtllib m.mtl\nusemtl white\n"
             "g floor\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n"
             "g lamp\nv 0.2 0.2 0.5\nv 0.2 0.8 0.5\nv 0.8 0.8 0.5\nv 0.8 0.2 0.5\nf 5 6 7 8\n");
  write_text(dir / "m.scene.json", R"({"mesh": "m.obj", "materials": [{"group": "lamp", "emission": 4}]})");
  const Scene scene = load_scene(dir / "m.scene.json").scene;
  const Material& lamp = material_of(scene, "lamp/");
  const Material& floor = material_of(scene, "floor/");
  EXPECT_EQ(lamp.emission, Rgb(4, 4, 4));
  EXPECT_EQ(lamp.reflectance, Rgb(0.8, 0.8, 0.8)) << "what the entry does not give stays as the file has it";
  EXPECT_EQ(lamp.name, "white (materials[0])");
  EXPECT_FALSE(floor.is_emitter());
  EXPECT_EQ(floor.name, "white");
  EXPECT_EQ(scene.materials.size(), 2u);
}

TEST(MaterialOverrides, AMaterialSelectorChangesItInPlaceAndLaterEntriesWin) {
  const auto dir = fresh_dir("override_material");
  write_text(dir / "m.mtl", "newmtl red\nKd 0.6 0.1 0.1\nnewmtl glow\nKd 0 0 0\nKe 1 1 1\n");
  write_text(dir / "m.obj",
             "mtllib m.mtl\n"
             "g floor\nusemtl red\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n"
             "g lamp\nusemtl glow\nv 0.2 0.2 0.5\nv 0.2 0.8 0.5\nv 0.8 0.8 0.5\nv 0.8 0.2 0.5\nf 5 6 7 8\n");
  write_text(dir / "m.scene.json",
             R"({"mesh": "m.obj", "materials": [
                  {"material": "red", "reflectance": [0.1, 0.2, 0.3]},
                  {"material": "glow", "emission": [2, 2, 2]},
                  {"group": "lamp", "material": "glow", "emission": [5, 6, 7]}]})");
  const Scene scene = load_scene(dir / "m.scene.json").scene;
  const Material& floor = material_of(scene, "floor/");
  EXPECT_EQ(floor.name, "red");
  EXPECT_EQ(floor.reflectance, Rgb(0.1, 0.2, 0.3));
  const Material& lamp = material_of(scene, "lamp/");
  EXPECT_EQ(lamp.name, "glow");
  EXPECT_EQ(lamp.emission, Rgb(5, 6, 7));
}

TEST(MaterialOverrides, PlyColoursAreSelectedByTheirMaterialName) {
  const auto dir = fresh_dir("override_rgb_name");
  write_lit_floor_plys(dir);
  write_text(dir / "s.scene.json",
             R"({"mesh": ["floor.ply", "light.ply"],
                 "materials": [{"material": "rgb_808080", "reflectance": 0.25}]})");
  const Scene scene = load_scene(dir / "s.scene.json").scene;
  for (const Surface& s : scene.surfaces) EXPECT_EQ(scene.materials[s.material].reflectance, Rgb(0.25, 0.25, 0.25));
}

TEST(MaterialOverrides, SeveralFilesKeepTheirOwnPointsAndFaces) {
  const auto dir = fresh_dir("override_several_files");
  write_lit_floor_plys(dir);
  write_text(dir / "s.scene.json", R"({"mesh": ["light.ply", "floor.ply"]})");
  const Scene scene = load_scene(dir / "s.scene.json").scene;
  ASSERT_EQ(scene.surfaces.size(), 2u);
  for (const Surface& s : scene.surfaces) {
    const bool is_light = s.name.rfind("light/", 0) == 0;
    ASSERT_TRUE(is_light || s.name.rfind("floor/", 0) == 0) << s.name;
    EXPECT_NEAR(s.area, is_light ? 0.36 : 1.0, 1e-6) << s.name;
    for (const Vec3& p : s.points) EXPECT_NEAR(p[2], is_light ? 0.5 : 0.0, 1e-6) << s.name;
  }
}

TEST(MaterialOverrides, ReflectanceOneFromAnOverrideIsWarnedAbout) {
  const auto dir = fresh_dir("override_white");
  write_lit_floor_plys(dir);
  write_text(dir / "s.scene.json",
             R"({"mesh": ["floor.ply", "light.ply"],
                 "materials": [{"file": "floor.ply", "reflectance": 1}, {"file": "light.ply", "emission": 1}]})");
  const LoadResult r = load_scene(dir / "s.scene.json");
  ASSERT_EQ(std::count_if(r.warnings.begin(), r.warnings.end(),
                          [](const std::string& w) { return w.find("reflectance 1") != std::string::npos; }),
            1);
  // The file's grey is overridden, so no warning names a file value.
  write_text(dir / "t.scene.json",
             R"({"mesh": ["floor.ply"], "materials": [{"file": "floor.ply", "reflectance": 0.5}]})");
  for (const std::string& w : load_scene(dir / "t.scene.json").warnings) {
    EXPECT_EQ(w.find("reflectance 1"), std::string::npos) << w;
  }
}

TEST(MaterialOverrides, EveryMistakeIsOneLineNamingTheSceneFileAndTheEntry) {
  const auto dir = fresh_dir("override_errors");
  write_lit_floor_plys(dir);
  struct Case {
    std::string materials;
    std::string expected;
  };
  const std::vector<Case> cases{
      {R"({"group": "lamp", "emission": 1})", "\"materials[0]\" selects no face: there is no group 'lamp'"},
      {R"({"material": "rgb_ffffff", "emission": 1})", "there is no material 'rgb_ffffff'"},
      {R"({"file": "floor.ply", "group": "light", "emission": 1})", "no face has everything it asks for"},
      {R"({"file": "lamp.ply", "emission": 1})", "\"materials[0].file\" 'lamp.ply' is not one of"},
      {R"({"emission": 1})", "selects nothing"},
      {R"({"group": "floor"})", "changes nothing"},
      {R"({"group": "floor", "reflectance": 1.2})", "must be in [0, 1]"},
      {R"({"group": "floor", "reflectance": [0.5, 0.5]})", "must be three numbers"},
      {R"({"group": "floor", "emission": [1, -1, 1]})", "non-negative"},
      {R"({"group": "floor", "emision": 1})", "unknown key \"materials[0].emision\""},
      {R"({"group": 3, "emission": 1})", "\"materials[0].group\" must be a name"},
      {R"("floor")", "\"materials[0]\" must be an object"},
  };
  for (const Case& c : cases) {
    write_text(dir / "s.scene.json",
               R"({"mesh": ["floor.ply", "light.ply"], "materials": [)" + c.materials + "]}");
    const std::string error = load_error(dir / "s.scene.json");
    EXPECT_NE(error.find("s.scene.json"), std::string::npos) << c.materials << ": " << error;
    EXPECT_NE(error.find(c.expected), std::string::npos) << c.materials << ": " << error;
    EXPECT_EQ(error.find('\n'), std::string::npos) << error;
  }
  write_text(dir / "s.scene.json", R"({"mesh": ["floor.ply", "floor.ply"]})");
  EXPECT_NE(load_error(dir / "s.scene.json").find("lists 'floor.ply' twice"), std::string::npos);
  write_text(dir / "s.scene.json", R"({"mesh": []})");
  EXPECT_NE(load_error(dir / "s.scene.json").find("non-empty list"), std::string::npos);
  write_text(dir / "s.scene.json", R"({"mesh": ["floor.ply", "gone.ply"]})");
  EXPECT_NE(load_error(dir / "s.scene.json").find("mesh file 'gone.ply' not found"), std::string::npos);
  write_text(dir / "s.scene.json", R"({"mesh": "floor.ply", "materials": {"group": "floor"}})");
  EXPECT_NE(load_error(dir / "s.scene.json").find("\"materials\" must be a list"), std::string::npos);
}

TEST(MaterialOverrides, TheSolveCommandLightsAPlyThroughItsSceneFile) {
  const auto dir = fresh_dir("override_solve_command");
  write_lit_floor_plys(dir);
  write_text(dir / "s.scene.json",
             R"({"mesh": ["floor.ply", "light.ply"],
                 "materials": [{"file": "light.ply", "reflectance": 0, "emission": 3}]})");
  const test::CommandResult r =
      test::run_lhr({"solve", (dir / "s.scene.json").string(), "--out", (dir / "out").string(), "--max-edge", "0.25"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err.find("no emitter"), std::string::npos) << r.err;
  EXPECT_TRUE(std::filesystem::exists(dir / "out" / "mesh.ply"));
}

}  // namespace
}  // namespace lhr
