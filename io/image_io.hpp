#pragma once
// Image files through OpenImageIO: PNG of display values, EXR of linear
// radiance (docs/design.md §5). Written atomically. The Image itself is
// mesh/image.hpp, so that renderers hold images without this file.

#include <array>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "io/atomic_file.hpp"
#include "mesh/image.hpp"
#include "mesh/scene.hpp"
#include "mesh/types.hpp"

namespace lhr {

// What a written image says about itself. An EXR stores the camera as
// OpenEXR's worldToCamera (x right, y up, z along the view: left-handed, as
// OpenEXR defines it) and worldToNDC (the view's corners at x, y = ±1),
// row-vector matrices as Imath's M44f.
struct ImageMetadata {
  std::string software;                                     // e.g. "lhr 0.1.0"
  std::optional<Camera> camera;                             // the view the pixels show
  std::vector<std::pair<std::string, std::string>> notes;   // further string attributes, e.g. {"lhr:units", ...}
};

// Writes by extension: .png (values in [0,1], 8 bit, clamped) or .exr
// (32-bit float, linear). Throws std::runtime_error naming the file.
void write_image(const std::filesystem::path& path, const Image& image, const ImageMetadata& metadata = {});
// The same, staged in a set of outputs published together.
void write_image(AtomicOutputs& outputs, const std::filesystem::path& path, const Image& image,
                 const ImageMetadata& metadata = {});

// The matrices written for a camera (row-vector convention, p' = p M):
// world to camera space and world to NDC before the perspective divide.
std::array<float, 16> world_to_camera_matrix(const Camera& camera);
std::array<float, 16> world_to_ndc_matrix(const Camera& camera);

// Reads any format OpenImageIO knows, first three channels (grey is
// replicated). Throws InputError naming the file.
Image read_image(const std::filesystem::path& path);

}  // namespace lhr
