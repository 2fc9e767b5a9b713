// Bad input must end in one line a user can act on, naming the file, from
// the library (InputError) and from the `lhr` command (exit code 1, no
// output written, no crash).

#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

#include "io/scene_loader.hpp"
#include "test_support.hpp"

namespace lhr {
namespace {

struct BadInput {
  std::string name;
  std::vector<std::pair<std::string, std::string>> files;  // name, content; the first is loaded
  std::string file_in_message;                             // the file the message must name
  std::string problem;                                     // a word of the message saying what is wrong
};

const char* const kCube =
    "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
    "f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 4 8 7 3\nf 1 5 8 4\nf 2 3 7 6\n";

// Names the case in test listings instead of dumping its bytes.
void PrintTo(const BadInput& c, std::ostream* os) { *os << c.name; }

std::string garbage() {
  // Fixed pseudo-random bytes (a 32-bit LCG), so the case is reproducible.
  std::string bytes;
  std::uint32_t x = 12345;
  for (int i = 0; i < 4096; ++i) {
    x = x * 1664525u + 1013904223u;
    bytes.push_back(static_cast<char>(x >> 24));
  }
  return bytes;
}

// A binary triangle whose face indices are cut off.
std::string truncated_binary_ply() {
  std::string ply =
      "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
      "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
  const float points[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  ply.append(reinterpret_cast<const char*>(points), sizeof points);
  ply.push_back(3);
  const std::int32_t first_index = 0;
  ply.append(reinterpret_cast<const char*>(&first_index), sizeof first_index);
  return ply;
}

// A binary OFF that declares far more faces than it holds.
std::string truncated_binary_off() {
  std::string off = "OFF BINARY\n";
  const std::int32_t counts[3] = {3, 1000000000, 0};
  off.append(reinterpret_cast<const char*>(counts), sizeof counts);
  const float points[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  off.append(reinterpret_cast<const char*>(points), sizeof points);
  return off;
}

const std::string kPlyHeader =
    "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
    "element face 2\nproperty list uchar int vertex_indices\nend_header\n";

std::vector<BadInput> cases() {
  const std::string cube = kCube;
  const std::string box_mtl_use = "mtllib box.mtl\nusemtl m\n";
  return {
      {"truncated_obj", {{"box.obj", cube.substr(0, cube.size() - 6)}}, "box.obj", "face"},
      {"truncated_obj_vertex", {{"box.obj", "v 0 0 0\nv 1 0 0\nv 1 1"}}, "box.obj", "coordinates"},
      {"binary_garbage_obj", {{"junk.obj", garbage()}}, "junk.obj", "binary"},
      {"binary_garbage_ply", {{"junk.ply", garbage()}}, "junk.ply", "PLY"},
      {"nan_coordinate", {{"nan.obj", "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n"}}, "nan.obj", "non-finite"},
      {"inf_coordinate", {{"inf.obj", "v 0 0 0\nv 1 0 0\nv 0 1e999 0\nf 1 2 3\n"}}, "inf.obj", "non-finite"},
      {"index_out_of_range",
       {{"range.obj", cube + "f 1 2 9\n"}},
       "range.obj:15",
       "out of range (8 vertices)"},
      {"index_zero", {{"zero.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n"}}, "zero.obj:4", "index 0"},
      {"empty_obj", {{"empty.obj", ""}}, "empty.obj", "no faces"},
      {"vertices_only_obj", {{"points.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n"}}, "points.obj", "no faces"},
      {"all_faces_zero_area",
       {{"flat.obj", "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n"}},
       "flat.obj",
       "zero area"},
      {"missing_mtl", {{"box.obj", "mtllib nothere.mtl\n" + cube}}, "nothere.mtl", "not found"},
      {"unknown_material",
       {{"box.obj", box_mtl_use + "usemtl nosuch\n" + cube}, {"box.mtl", "newmtl m\nKd 0.5 0.5 0.5\n"}},
       "box.obj:3",
       "nosuch"},
      {"usemtl_before_mtllib",
       {{"box.obj", "usemtl m\nmtllib box.mtl\n" + cube}, {"box.mtl", "newmtl m\nKd 0.5 0.5 0.5\n"}},
       "box.obj:1",
       "unknown material"},
      {"repeated_vertex", {{"rep.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 2\n"}}, "rep.obj:4", "distinct"},
      {"two_vertex_face", {{"two.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2\n"}}, "two.obj:4", "at least 3"},
      {"kd_above_one",
       {{"box.obj", box_mtl_use + cube}, {"box.mtl", "newmtl m\nKd 1.2 0.5 0.5\n"}},
       "box.mtl:2",
       "Kd"},
      {"kd_negative",
       {{"box.obj", box_mtl_use + cube}, {"box.mtl", "newmtl m\nKd 0.5 -0.1 0.5\n"}},
       "box.mtl:2",
       "outside [0, 1]"},
      {"vt_index_out_of_range",
       {{"vt.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nf 1/1 2/2 3/3\n"}},
       "vt.obj:6",
       "texture coordinate index 3 out of range (2 vt lines)"},
      {"vn_index_out_of_range",
       {{"vn.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//1 3//-2\n"}},
       "vn.obj:5",
       "normal index -2 out of range (1 vn lines)"},
      {"mtllib_with_space_missing",
       {{"box.obj", "mtllib my room.mtl\n" + cube}},
       "box.obj:1",
       "'my room.mtl' not found"},
      {"off_colour_byte_out_of_range",
       {{"tri.off", "COFF\n3 1 0\n0 0 0 255 0 0\n1 0 0 300 0 0\n0 1 0 0 0 0\n3 0 1 2\n"}},
       "tri.off:4",
       "0..255"},
      {"off_float_colour_above_one",
       {{"tri.off", "COFF\n3 1 0\n0 0 0 1.5 0 0 1\n1 0 0 0 0 0 1\n0 1 0 0 0 0 1\n3 0 1 2\n"}},
       "tri.off:3",
       "[0, 1]"},
      {"coff_vertex_without_colour",
       {{"tri.off", "COFF\n3 1 0\n0 0 0 1 0 0\n1 0 0\n0 1 0 0 0 0\n3 0 1 2\n"}},
       "tri.off:4",
       "3 or 4 colour components"},
      {"off_face_colour_of_two_values",
       {{"tri.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2 0.5 0.5\n"}},
       "tri.off:6",
       "a face colour is"},
      {"ke_negative",
       {{"box.obj", box_mtl_use + cube}, {"box.mtl", "newmtl m\nKd 0.5 0.5 0.5\nKe -1 0 0\n"}},
       "box.mtl:3",
       "Ke"},
      {"ke_nan", {{"box.obj", box_mtl_use + cube}, {"box.mtl", "newmtl m\nKe 1 nan 0\n"}}, "box.mtl:2", "Ke"},
      {"bad_json",
       {{"bad.scene.json", "{\n  \"mesh\": \"box.obj\",\n  \"camera\": {\n}\n"}, {"box.obj", cube}},
       "bad.scene.json:",
       "JSON"},
      {"json_missing_mesh_key", {{"nomesh.scene.json", "{\"camera\": 3}"}}, "nomesh.scene.json", "mesh"},
      {"json_wrong_type",
       {{"cam.scene.json", R"({"mesh": "box.obj", "camera": {"eye": [0,0,3], "target": [0,0,0], "up": [0,1,0],
          "fov_y_deg": "wide", "width": 10, "height": 10}})"},
        {"box.obj", cube}},
       "cam.scene.json",
       "fov_y_deg"},
      {"json_eye_is_target",
       {{"cam.scene.json", R"({"mesh": "box.obj", "camera": {"eye": [1,1,1], "target": [1,1,1], "up": [0,1,0],
          "fov_y_deg": 40, "width": 10, "height": 10}})"},
        {"box.obj", cube}},
       "cam.scene.json",
       "same point"},
      {"json_fov_out_of_range",
       {{"cam.scene.json", R"({"mesh": "box.obj", "camera": {"eye": [0,0,3], "target": [0,0,0], "up": [0,1,0],
          "fov_y_deg": 180, "width": 10, "height": 10}})"},
        {"box.obj", cube}},
       "cam.scene.json",
       "(0, 180)"},
      {"json_zero_width",
       {{"cam.scene.json", R"({"mesh": "box.obj", "camera": {"eye": [0,0,3], "target": [0,0,0], "up": [0,1,0],
          "fov_y_deg": 40, "width": 0, "height": 10}})"},
        {"box.obj", cube}},
       "cam.scene.json",
       "width"},
      {"json_missing_mesh_file", {{"scene.scene.json", R"({"mesh": "gone.obj"})"}}, "gone.obj", "not found"},
      {"truncated_ply",
       {{"quad.ply", kPlyHeader + "0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n3 0"}},
       "quad.ply",
       "face"},
      {"truncated_binary_ply", {{"tri.ply", truncated_binary_ply()}}, "tri.ply", "truncated"},
      {"truncated_ply_header",
       {{"quad.ply", "ply\nformat ascii 1.0\nelement vertex 4\n"}},
       "quad.ply",
       "end_header"},
      {"ply_index_out_of_range",
       {{"quad.ply", kPlyHeader + "0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n3 0 2 4\n"}},
       "quad.ply:15",
       "out of range (4 vertices)"},
      {"ply_nan",
       {{"quad.ply", kPlyHeader + "0 0 0\n1 nan 0\n1 1 0\n0 1 0\n3 0 1 2\n3 0 2 3\n"}},
       "quad.ply:11",
       "non-finite"},
      {"off_too_few_vertices",
       {{"few.off", "OFF\n8 1 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n"}},
       "few.off",
       "truncated"},
      // Blank lines and comments pass the count check; the list itself ends.
      {"off_vertices_end_among_blank_lines",
       {{"tri.off", "OFF\n3 1 0\n0 0 0\n\n# no more\n\n\n"}},
       "tri.off",
       "file ends after 1 of 3 vertices (truncated file?)"},
      {"off_faces_end_among_blank_lines",
       {{"tri.off", "OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n\n\n"}},
       "tri.off",
       "file ends after 1 of 2 faces (truncated file?)"},
      {"off_index_out_of_range",
       {{"tri.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n"}},
       "tri.off:6",
       "out of range (3 vertices)"},
      {"truncated_binary_off", {{"tri.off", truncated_binary_off()}}, "tri.off", "truncated"},
      {"off_garbage", {{"junk.off", garbage()}}, "junk.off", "binary"},
      {"unsupported_extension", {{"box.stl", "solid x\nendsolid x\n"}}, "box.stl", "unsupported"},
  };
}

class BadInputTest : public testing::TestWithParam<BadInput> {
 protected:
  std::filesystem::path write_case() {
    const BadInput& c = GetParam();
    const auto dir = test::fresh_dir("bad_" + c.name);
    for (const auto& [name, content] : c.files) test::write_text(dir / name, content);
    return dir / c.files.front().first;
  }
};

TEST_P(BadInputTest, LibraryThrowsOneLineInputErrorNamingTheFile) {
  const auto path = write_case();
  try {
    load_scene(path);
    FAIL() << "no error for " << path;
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find(GetParam().file_in_message), std::string::npos) << what;
    EXPECT_NE(what.find(GetParam().problem), std::string::npos) << what;
    EXPECT_EQ(what.find('\n'), std::string::npos) << what;
    EXPECT_EQ(what.find('\r'), std::string::npos) << what;
  }
}

TEST_P(BadInputTest, CommandFailsWithOneLineAndWritesNothing) {
  const auto path = write_case();
  const auto out = path.parent_path() / "out.ply";
  const test::CommandResult r = test::run_lhr({"mesh", path.string(), "--out", out.string()});
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_EQ(test::count_lines(r.err), 1) << r.err;
  EXPECT_NE(r.err.find(GetParam().file_in_message), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(out));
}

// Kd = 1 is what many files in the wild use (tinyobjloader's cube.obj, the
// Cornell box): it loads, for every command, with one warning naming the
// materials; Kd 1.2 is one line naming the MTL line.
TEST(MaterialRange, KdOneWarnsOnceAndKdAboveOneIsOneLine) {
  const auto dir = test::fresh_dir("kd_range");
  test::write_text(dir / "cube.mtl", "newmtl white\nKd 1 1 1\nnewmtl red\nKd 1 0 0\n");
  test::write_text(dir / "cube.obj", "mtllib cube.mtl\nusemtl white\n" + std::string(kCube).substr(0, 64) +
                                         "f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nusemtl red\nf 4 8 7 3\nf 1 5 8 4\n"
                                         "f 2 3 7 6\n");
  const auto r = test::run_lhr({"mesh", (dir / "cube.obj").string(), "--out", (dir / "out.ply").string()});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  int warnings = 0;
  std::string warning;
  for (std::size_t at = r.err.find("warning"); at != std::string::npos; at = r.err.find("warning", at + 1)) {
    ++warnings;
    warning = r.err.substr(at, r.err.find('\n', at) - at);
  }
  EXPECT_EQ(warnings, 1) << r.err;
  EXPECT_NE(warning.find("'white', 'red'"), std::string::npos) << r.err;
  EXPECT_TRUE(std::filesystem::exists(dir / "out.ply"));

  test::write_text(dir / "cube.mtl", "newmtl white\nKd 1.2 1 1\nnewmtl red\nKd 1 0 0\n");
  const auto bad = test::run_lhr({"mesh", (dir / "cube.obj").string(), "--out", (dir / "bad.ply").string()});
  EXPECT_EQ(bad.exit_code, 1) << bad.err;
  EXPECT_EQ(test::count_lines(bad.err), 1) << bad.err;
  EXPECT_NE(bad.err.find("cube.mtl:2"), std::string::npos) << bad.err;
  EXPECT_NE(bad.err.find("Kd 1.2"), std::string::npos) << bad.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "bad.ply"));
}

INSTANTIATE_TEST_SUITE_P(Cases, BadInputTest, testing::ValuesIn(cases()),
                         [](const testing::TestParamInfo<BadInput>& info) { return info.param.name; });

}  // namespace
}  // namespace lhr
