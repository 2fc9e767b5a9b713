#pragma once
// The mean colour of an image texture, as a diffuse reflectance (docs/design.md §3):
// lhr's surfaces carry one reflectance each, so an MTL material that gives
// only a `map_Kd` texture reflects the texture's average.

#include <filesystem>

#include "io/input_error.hpp"
#include "mesh/types.hpp"

namespace lhr {

// Mean linear RGB of the image's pixels (alpha ignored, grey replicated).
// 8- and 16-bit images are taken as sRGB-encoded, as painted and
// photographed textures are, and decoded before averaging; float images
// (EXR, HDR) are taken as linear. Throws InputError naming the file.
Rgb texture_mean_colour(const std::filesystem::path& path);

}  // namespace lhr
