#pragma once
// The material of faces that name none (an OBJ face before any usemtl, a
// PLY/OFF face without colours), io/ internal.

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

}  // namespace lhr
