#pragma once
// The paper's test scenes (§6), generated: "two rooms" (four lights each,
// furniture, ~386 initial surfaces) and "four rooms" (two lights each, a table
// per room, ~296 surfaces).

#include <string>
#include <vector>

#include "mesh/scene.hpp"

namespace lhr {

struct PaperScene {
  PolygonSoup soup;
  Camera camera;
};

std::vector<std::string> paper_scene_names();  // {"two-rooms", "four-rooms"}
// Throws std::invalid_argument for an unknown name.
PaperScene make_paper_scene(const std::string& name);

}  // namespace lhr
