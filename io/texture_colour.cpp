#include "io/texture_colour.hpp"

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace lhr {

namespace {

double srgb_to_linear(double v) { return v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4); }

}  // namespace

Rgb texture_mean_colour(const std::filesystem::path& path) {
  auto in = OIIO::ImageInput::open(path.string());
  if (!in) throw InputError(path, "cannot read texture: " + OIIO::geterror());
  const OIIO::ImageSpec& spec = in->spec();
  if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0) throw InputError(path, "texture has no pixels");
  const std::size_t pixels = static_cast<std::size_t>(spec.width) * spec.height;
  std::vector<float> all(pixels * spec.nchannels);
  if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, all.data())) {
    throw InputError(path, "cannot read texture pixels: " + in->geterror());
  }
  const std::string space = spec.get_string_attribute("oiio:ColorSpace");
  const bool encoded = spec.format.is_floating_point() ? (space == "sRGB") : (space != "Linear" && space != "linear");
  // Grey with alpha has two channels; colour images have three or more.
  const int colour_channels = spec.nchannels < 3 ? 1 : 3;
  Rgb sum(0.0, 0.0, 0.0);
  for (std::size_t i = 0; i < pixels; ++i) {
    for (int k = 0; k < 3; ++k) {
      const double v = std::clamp(static_cast<double>(all[i * spec.nchannels + std::min(k, colour_channels - 1)]),
                                  0.0, 1.0);
      sum[k] += encoded ? srgb_to_linear(v) : v;
    }
  }
  return sum / static_cast<double>(pixels);
}

}  // namespace lhr
