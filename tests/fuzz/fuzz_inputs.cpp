#include "tests/fuzz/fuzz_inputs.hpp"

#include <string>

#include "io/mesh_io.hpp"
#include "tests/fuzz/fuzz_support.hpp"

namespace lhr::fuzz {

namespace {

// A unit floor lit by a smaller, facing quad above it.
constexpr std::string_view kRoomObj =
    "mtllib room.mtl\n"
    "usemtl white\n"
    "v 0 0 0\nv 1 0 0\nv 1 0 1\nv 0 0 1\n"
    "f 1 4 3 2\n"
    "usemtl light\n"
    "v 0.25 1 0.25\nv 0.75 1 0.25\nv 0.75 1 0.75\nv 0.25 1 0.75\n"
    "f 5 6 7 8\n";
constexpr std::string_view kRoomMtl =
    "newmtl white\nKd 0.7 0.7 0.7\nKe 0 0 0\n"
    "newmtl light\nKd 0.5 0.5 0.5\nKe 10 10 10\n";
constexpr std::string_view kRoomPly =
    "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
    "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
    "0 0 0\n0 0 1\n1 0 1\n1 0 0\n4 0 1 2 3\n";
constexpr std::string_view kRoomOff = "OFF\n4 1 0\n0 0 0\n0 0 1\n1 0 1\n1 0 0\n4 0 1 2 3\n";

void run_mesh_file(std::string_view input, const char* name) {
  const auto path = scratch_dir() / name;
  write_file(path, input);
  expect_clean([&] { check_soup(load_polygon_soup(path)); });
  expect_clean([&] { check_scene(load_scene(path)); });
  expect_clean([&] { check_raw(read_raw_mesh(path)); });
  check_no_leftovers({name});
  remove_file(path);
}

}  // namespace

void run_obj(std::string_view input) {
  const auto obj = scratch_dir() / "fuzz.obj";
  const auto mtl = scratch_dir() / "fuzz.mtl";
  const std::size_t at = input.find(kMtlMarker);
  write_file(obj, input.substr(0, at));
  if (at == std::string_view::npos) {
    remove_file(mtl);
  } else {
    write_file(mtl, input.substr(at + kMtlMarker.size()));
  }
  expect_clean([&] { check_soup(load_polygon_soup(obj)); });
  expect_clean([&] { check_scene(load_scene(obj)); });
  check_no_leftovers({"fuzz.obj", "fuzz.mtl"});
  remove_file(obj);
  remove_file(mtl);
}

void run_ply(std::string_view input) { run_mesh_file(input, "fuzz.ply"); }

void run_off(std::string_view input) { run_mesh_file(input, "fuzz.off"); }

void run_scene_json(std::string_view input) {
  const auto& dir = scratch_dir();
  static const bool room_written = [&] {
    write_file(dir / "room.obj", kRoomObj);
    write_file(dir / "room.mtl", kRoomMtl);
    write_file(dir / "room.ply", kRoomPly);
    write_file(dir / "room.off", kRoomOff);
    return true;
  }();
  (void)room_written;
  const auto scene = dir / "fuzz.scene.json";
  write_file(scene, input);
  expect_clean([&] { check_scene(load_scene(scene)); });
  check_no_leftovers({"fuzz.scene.json", "room.obj", "room.mtl", "room.ply", "room.off"});
  remove_file(scene);
}

}  // namespace lhr::fuzz
