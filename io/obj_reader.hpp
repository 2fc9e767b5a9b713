#pragma once
// OBJ files with their MTL libraries, checked and built in one pass over the
// OBJ (io/ internal; load_polygon_soup and load_scene in
// io/scene_loader.hpp are the public entry points).

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "mesh/scene.hpp"

namespace lhr {

// The polygon soup of an OBJ: its vertices as written (correctly rounded),
// faces in file order with their group (g or o line) and material (usemtl).
// What is accepted but worth knowing goes to warnings. checkpoint, when
// set, is called every few thousand lines, so a long parse can be stopped
// by what it throws. Throws InputError.
PolygonSoup read_obj(const std::filesystem::path& path, std::vector<std::string>& warnings,
                     const std::function<void()>& checkpoint = {});

}  // namespace lhr
