#include "io/texture_colour.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "io/image_codecs.hpp"

namespace lhr {

namespace {

double srgb_to_linear(double v) { return v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4); }

}  // namespace

Rgb texture_mean_colour(const std::filesystem::path& path) {
  image_codecs::DecodedImage decoded;
  image_codecs::DecodeFailure failure;
  const std::string error = image_codecs::codecs().decode(path.string(), decoded, failure);
  if (failure == image_codecs::DecodeFailure::kOpen) throw InputError(path, "cannot read texture: " + error);
  if (failure == image_codecs::DecodeFailure::kPixels) throw InputError(path, "cannot read texture pixels: " + error);
  if (decoded.pixels.empty()) throw InputError(path, "texture has no pixels");
  const std::size_t pixels = static_cast<std::size_t>(decoded.width) * decoded.height;
  const int channels = decoded.channels;
  const std::string& space = decoded.colour_space;
  const bool encoded = decoded.floating_point ? (space == "sRGB") : (space != "Linear" && space != "linear");
  // Grey with alpha has two channels; colour images have three or more.
  const int colour_channels = channels < 3 ? 1 : 3;
  Rgb sum(0.0, 0.0, 0.0);
  for (std::size_t i = 0; i < pixels; ++i) {
    for (int k = 0; k < 3; ++k) {
      const double v = std::clamp(static_cast<double>(decoded.pixels[i * channels + std::min(k, colour_channels - 1)]),
                                  0.0, 1.0);
      sum[k] += encoded ? srgb_to_linear(v) : v;
    }
  }
  return sum / static_cast<double>(pixels);
}

}  // namespace lhr
