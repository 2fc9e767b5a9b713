#pragma once
// Materials assigned or overridden by a scene file (docs/scene-format.md,
// "materials"): a PLY or OFF scene gets its emitters this way, and a file
// from another tool its intended reflectances, without editing the file.

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "mesh/scene.hpp"

namespace lhr {

// One entry of the scene file's "materials" array. A face is selected when
// every selector given matches it; later entries win over earlier ones.
struct MaterialOverride {
  std::string where;                   // "materials[2]", for messages
  std::optional<std::string> file;     // a "mesh" entry, as written or by its file name
  std::optional<std::string> group;    // OBJ object/group; a PLY/OFF file is one group named after it
  std::optional<std::string> material; // the material name in the geometry file (PLY/OFF: rgb_RRGGBB)
  std::optional<Rgb> reflectance;      // Kd, each channel in [0, 1]
  std::optional<Rgb> emission;         // Ke, finite and >= 0
};

// Where each face of a soup came from, for the selectors.
struct SoupOrigin {
  std::vector<std::string> file_names;      // the scene file's "mesh" entries, as written
  std::vector<int> face_file;               // per face, an index into file_names
  std::vector<std::string> material_names;  // per material, its name in its geometry file
};

// Gives every face the overridden material its selectors ask for. A
// material whose faces all receive the same overrides is changed in place;
// one that some faces keep is split, the overridden copy named after the
// entries that made it. Unused materials are dropped. An entry that selects
// no face is an error naming scene_file: it is a typo more often than not.
void apply_material_overrides(PolygonSoup& soup, const SoupOrigin& origin,
                              const std::vector<MaterialOverride>& overrides,
                              const std::filesystem::path& scene_file);

}  // namespace lhr
