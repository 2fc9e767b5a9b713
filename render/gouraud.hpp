#pragma once
// Gouraud view of a solution (paper §4.1: the image is the linear
// interpolation of vertex values over the triangle seen at each pixel;
// docs/design.md §5): one Embree primary ray per pixel centre, barycentric
// interpolation over the conforming leaf triangle hit.

#include <cstdint>
#include <vector>

#include "mesh/image.hpp"
#include "mesh/scene.hpp"
#include "mesh/types.hpp"
#include "radiosity/linear_solver.hpp"

namespace lhr {

// What each pixel's primary ray hit, traced once and shaded as often as needed
// (linear radiance for EXR, display values for PNG).
struct PixelHits {
  int width = 0, height = 0;
  struct Hit {
    std::int32_t surface = -1;  // -1: background
    std::int32_t face = -1;
    float u = 0, v = 0;  // barycentrics of the face's corners 1 and 2
    // The back of a face: black, and no importance (docs/design.md §3:
    // only the front reflects and emits), but still a pixel of the scene.
    bool back = false;
  };
  std::vector<Hit> pixels;  // row-major, row 0 at the top
  std::vector<std::uint8_t> mask() const;  // 1 where a surface is seen
};

PixelHits trace_pixels(const Camera& camera, const std::vector<const TriMesh*>& meshes);

// The fronts the camera sees, one sample per pixel: the linear solver's
// importance (paper §4.1). The back of a face is black whatever its mesh
// holds, so it asks for no refinement.
std::vector<ViewSample> view_samples(const Camera& camera, const std::vector<const TriMesh*>& meshes);

// values[s][v]: value at vertex v of meshes[s]. Background pixels and the
// backs of faces are black.
Image shade_gouraud(const PixelHits& hits, const std::vector<const TriMesh*>& meshes,
                    const std::vector<const std::vector<Rgb>*>& values);

}  // namespace lhr
