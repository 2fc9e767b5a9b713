#include "render/image_metrics.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace lhr {

namespace {

constexpr double kNear = 0.10;
constexpr double kFar = 0.15;

void check_sizes(const Image& image, const Image& reference, const std::vector<std::uint8_t>& mask) {
  if (image.width != reference.width || image.height != reference.height) {
    throw std::invalid_argument("the image is " + std::to_string(image.width) + "x" + std::to_string(image.height) +
                                " pixels and the reference " + std::to_string(reference.width) + "x" +
                                std::to_string(reference.height));
  }
  if (mask.size() != static_cast<std::size_t>(reference.width) * reference.height) {
    throw std::invalid_argument("the background mask does not match the image size");
  }
}

Rgb pixel_rgb(const Image& image, std::size_t i) {
  return Rgb(image.rgb[3 * i], image.rgb[3 * i + 1], image.rgb[3 * i + 2]);
}

}  // namespace

std::vector<std::uint8_t> nonzero_mask(const Image& reference) {
  const std::size_t n = static_cast<std::size_t>(reference.width) * reference.height;
  std::vector<std::uint8_t> mask(n);
  for (std::size_t i = 0; i < n; ++i) {
    const float* p = &reference.rgb[3 * i];
    mask[i] = (p[0] != 0.0f || p[1] != 0.0f || p[2] != 0.0f) ? 1 : 0;
  }
  return mask;
}

std::unique_ptr<ToneMap> reference_tone_map(const ToneMapChoice& tone, const Image& reference,
                                            const std::vector<std::uint8_t>& mask) {
  if (mask.size() != static_cast<std::size_t>(reference.width) * reference.height) {
    throw std::invalid_argument("the background mask does not match the image size");
  }
  double brightest = 0.0;
  for (std::size_t i = 0; i < mask.size(); ++i) {
    if (mask[i]) brightest = std::max(brightest, luminance(pixel_rgb(reference, i)));
  }
  return make_tone_map(tone, log_average_luminance(reference, mask), brightest);
}

ImageMetrics compare_images(const Image& image, const Image& reference, const std::vector<std::uint8_t>& mask,
                            const ToneMap& tone) {
  check_sizes(image, reference, mask);
  ImageMetrics m;
  std::size_t near = 0, far = 0;
  double squares = 0.0, abs_difference = 0.0, abs_reference = 0.0;
  for (std::size_t i = 0; i < mask.size(); ++i) {
    if (!mask[i]) continue;
    const Rgb a = pixel_rgb(image, i), b = pixel_rgb(reference, i);
    const Rgb da = tone.display_rgb(a), db = tone.display_rgb(b);
    double difference = 0.0;
    for (int c = 0; c < 3; ++c) {
      const double d = std::abs(da[c] - db[c]);
      difference = std::max(difference, d);
      squares += d * d;
      abs_difference += std::abs(a[c] - b[c]);
      abs_reference += std::abs(b[c]);
    }
    near += difference <= kNear;
    far += difference <= kFar;
    m.max_difference = std::max(m.max_difference, difference);
    ++m.pixels;
  }
  if (m.pixels == 0) return m;
  const double n = static_cast<double>(m.pixels);
  m.within_10 = 100.0 * static_cast<double>(near) / n;
  m.within_15 = 100.0 * static_cast<double>(far) / n;
  m.rmse = std::sqrt(squares / (3.0 * n));
  m.psnr_db = m.rmse > 0 ? -20.0 * std::log10(m.rmse) : std::numeric_limits<double>::infinity();
  m.relative_error = abs_reference > 0   ? abs_difference / abs_reference
                     : abs_difference > 0 ? std::numeric_limits<double>::infinity()
                                          : 0.0;
  return m;
}

Image difference_image(const Image& image, const Image& reference, const std::vector<std::uint8_t>& mask,
                       const ToneMap& tone) {
  check_sizes(image, reference, mask);
  Image out(reference.width, reference.height);
  for (std::size_t i = 0; i < mask.size(); ++i) {
    if (!mask[i]) continue;
    const Rgb da = tone.display_rgb(pixel_rgb(image, i)), db = tone.display_rgb(pixel_rgb(reference, i));
    const double d = std::max({std::abs(da[0] - db[0]), std::abs(da[1] - db[1]), std::abs(da[2] - db[2])});
    float* p = &out.rgb[3 * i];
    if (d <= kNear) {
      // Dark grey even at zero difference, so compared pixels stand out from the background.
      const float g = static_cast<float>(0.15 + 0.6 * d / kNear);
      p[0] = p[1] = p[2] = g;
    } else if (d <= kFar) {
      p[0] = 1.0f, p[1] = 0.85f, p[2] = 0.0f;
    } else {
      p[0] = 1.0f, p[1] = 0.0f, p[2] = 0.0f;
    }
  }
  return out;
}

}  // namespace lhr
