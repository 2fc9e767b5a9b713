#pragma once
// A scene file (docs/scene-format.md, "Scene file"): the JSON that names the
// geometry and carries the camera, the settings and the material overrides.

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "io/material_overrides.hpp"
#include "mesh/scene.hpp"

namespace lhr {

struct SceneFile {
  std::vector<std::filesystem::path> meshes;  // resolved against the scene file's folder; each exists
  std::vector<std::string> mesh_entries;      // as written, for the "file" selector
  std::optional<Camera> camera;
  SceneSettings settings;
  std::vector<MaterialOverride> overrides;
};

// Reads and checks every key; an error is one InputError naming the file
// and the key (or the JSON's line).
SceneFile parse_scene_file(const std::filesystem::path& path);

}  // namespace lhr
