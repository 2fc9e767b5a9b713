#pragma once
// What each loader fuzzer does with one input, shared by the libFuzzer
// harnesses (fuzz_NAME.cpp) and by test_fuzz_corpus, which replays the seed
// and regression corpus in every build. A finding aborts (fuzz_support.hpp).

#include <string_view>

namespace lhr::fuzz {

// The input is split at kMtlMarker: the bytes before it are fuzz.obj, the
// bytes after it fuzz.mtl (absent without the marker), so inputs reach the
// MTL checks through "mtllib fuzz.mtl". Runs load_polygon_soup and load_scene.
inline constexpr std::string_view kMtlMarker = "\n#@mtl@\n";
void run_obj(std::string_view input);

// load_polygon_soup, load_scene, and read_raw_mesh followed by the
// conforming check, as `lhr validate` runs them.
void run_ply(std::string_view input);
void run_off(std::string_view input);

// The input is fuzz.scene.json; beside it lie small valid meshes (room.obj
// with room.mtl, room.ply, room.off) for its "mesh" key to name, so inputs
// that pass the JSON checks go on to load a scene.
void run_scene_json(std::string_view input);

}  // namespace lhr::fuzz
