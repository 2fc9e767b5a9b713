#pragma once
// Image files through OpenImageIO: PNG of display values, EXR of linear
// radiance (docs/design.md §5). Written atomically.

#include <filesystem>
#include <vector>

#include "io/atomic_file.hpp"
#include "mesh/types.hpp"

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

// Writes by extension: .png (values in [0,1], 8 bit, clamped) or .exr
// (half float, linear). Throws std::runtime_error naming the file.
void write_image(const std::filesystem::path& path, const Image& image);
// The same, staged in a set of outputs published together.
void write_image(AtomicOutputs& outputs, const std::filesystem::path& path, const Image& image);

// Reads any format OpenImageIO knows, first three channels (grey is
// replicated). Throws InputError naming the file.
Image read_image(const std::filesystem::path& path);

}  // namespace lhr
