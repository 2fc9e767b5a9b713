#pragma once
// Per-surface means of an image against its reference (docs/design.md §5 "How
// accuracy is judged": per-surface means back the pixel norms). A solver's
// bias is regional — one face too bright, another too dark — and a pixel
// count hides which; the mean linear radiance of each surface over the
// pixels where the camera sees it names the surface.

#include <cstdint>
#include <vector>

#include "mesh/image.hpp"
#include "mesh/types.hpp"

namespace lhr {

struct SurfaceComparison {
  std::size_t pixels = 0;  // where the camera sees this surface
  Rgb image{0, 0, 0};      // mean linear radiance over those pixels
  Rgb reference{0, 0, 0};
  // image / reference of the means' luminance; 0 when the reference's is 0.
  double luminance_ratio() const;
  // Per channel; 0 where the reference's channel is 0.
  Rgb ratio() const;
};

// pixel_surface: per pixel, the surface index seen there or -1
// (PathTracer::pixel_surfaces). One entry per surface, 0 .. num_surfaces−1.
// Throws std::invalid_argument when the sizes differ or an index is out of range.
std::vector<SurfaceComparison> compare_surfaces(const Image& image, const Image& reference,
                                                const std::vector<std::int32_t>& pixel_surface, int num_surfaces);

}  // namespace lhr
