#pragma once
// Scene loading (docs/design.md §3): NAME.scene.json with camera and settings, or a
// bare OBJ/MTL, PLY or OFF. All errors are InputError with one line naming
// file and line/element.

#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "io/input_error.hpp"
#include "mesh/scene.hpp"

namespace lhr {

struct LoadOptions {
  std::optional<double> crease_angle_deg;  // overrides the scene file
  // Called between slices of each file's read, every few thousand lines or
  // elements of its parse and every few thousand faces of the split into
  // surfaces: what it throws (an interrupt) ends the load.
  std::function<void()> checkpoint;
};

struct LoadResult {
  Scene scene;
  std::vector<std::string> warnings;  // e.g. "dropped 3 zero-area faces"
};

LoadResult load_scene(const std::filesystem::path& path, const LoadOptions& options = {});

// The polygon soup of one geometry file (OBJ with its MTL, PLY, OFF),
// validated; what is accepted but worth knowing (ignored MTL keys,
// reflectance 1, a missing texture) is added to warnings when given.
PolygonSoup load_polygon_soup(const std::filesystem::path& path, std::vector<std::string>* warnings = nullptr);

}  // namespace lhr
