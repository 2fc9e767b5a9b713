#pragma once
// An image in memory: a plain value, with no file format attached. It lives
// in the lowest layer, beside the Camera whose pixels it holds (docs/design.md
// §2, §3), so that the renderers (render/) make, compare and return images
// without depending on io/, and io/image_io reads and writes them without
// depending on render/.

#include <cstddef>
#include <vector>

namespace lhr {

// Row-major RGB, row 0 at the top (pixel (0,0) is top-left, docs/design.md §3).
struct Image {
  int width = 0;
  int height = 0;
  std::vector<float> rgb;  // 3 * width * height

  Image() = default;
  Image(int w, int h) : width(w), height(h), rgb(3 * static_cast<std::size_t>(w) * h, 0.0f) {}
  float* pixel(int x, int y) { return &rgb[3 * (static_cast<std::size_t>(y) * width + x)]; }
  const float* pixel(int x, int y) const { return &rgb[3 * (static_cast<std::size_t>(y) * width + x)]; }
};

}  // namespace lhr
