#pragma once
// The material of faces that name none (an OBJ face before any usemtl, a
// PLY/OFF face without colours), io/ internal.

#include <vector>

#include "mesh/scene.hpp"

namespace lhr {

// Faces without a material, and materials whose only colour is a texture
// that cannot be found, reflect this grey (docs/design.md §3).
inline constexpr double kDefaultGrey = 0.5;

inline Material default_material() {
  Material grey;
  grey.name = "default";
  grey.reflectance = Rgb(kDefaultGrey, kDefaultGrey, kDefaultGrey);
  return grey;
}

// The default material's index among materials, appended when a face
// first needs it: index stays < 0 until then, so a file whose faces all
// have materials gains none.
inline int default_material_index(std::vector<Material>& materials, int& index) {
  if (index < 0) {
    index = static_cast<int>(materials.size());
    materials.push_back(default_material());
  }
  return index;
}

}  // namespace lhr
