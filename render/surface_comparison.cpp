#include "render/surface_comparison.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "radiosity/tone_map.hpp"

namespace lhr {

double SurfaceComparison::luminance_ratio() const {
  const double r = luminance(reference);
  return r > 0 ? luminance(image) / r : 0.0;
}

Rgb SurfaceComparison::ratio() const {
  Rgb out(0, 0, 0);
  for (int c = 0; c < 3; ++c) out[c] = reference[c] > 0 ? image[c] / reference[c] : 0.0;
  return out;
}

std::vector<SurfaceComparison> compare_surfaces(const Image& image, const Image& reference,
                                                const std::vector<std::int32_t>& pixel_surface, int num_surfaces) {
  const std::size_t n = static_cast<std::size_t>(reference.width) * static_cast<std::size_t>(reference.height);
  if (image.width != reference.width || image.height != reference.height || pixel_surface.size() != n ||
      image.rgb.size() != 3 * n || reference.rgb.size() != 3 * n) {
    throw std::invalid_argument("compare_surfaces: the image, the reference and the surface map differ in size");
  }
  std::vector<SurfaceComparison> out(static_cast<std::size_t>(std::max(num_surfaces, 0)));
  for (std::size_t i = 0; i < n; ++i) {
    const std::int32_t s = pixel_surface[i];
    if (s < 0) continue;
    if (s >= num_surfaces) {
      throw std::invalid_argument("compare_surfaces: pixel " + std::to_string(i) + " names surface " +
                                  std::to_string(s) + " of " + std::to_string(num_surfaces));
    }
    SurfaceComparison& c = out[s];
    ++c.pixels;
    for (int k = 0; k < 3; ++k) {
      c.image[k] += image.rgb[3 * i + k];
      c.reference[k] += reference.rgb[3 * i + k];
    }
  }
  for (SurfaceComparison& c : out) {
    if (c.pixels == 0) continue;
    c.image /= static_cast<double>(c.pixels);
    c.reference /= static_cast<double>(c.pixels);
  }
  return out;
}

}  // namespace lhr
