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

double pixel_luminance(const Image& image, std::size_t i) { return luminance(pixel_rgb(image, i)); }

struct LuminanceSums {
  std::size_t pixels = 0;
  double image = 0.0;
  double reference = 0.0;
};

LuminanceSums luminance_sums(const Image& image, const Image& reference, const std::vector<std::uint8_t>& mask) {
  LuminanceSums sums;
  for (std::size_t i = 0; i < mask.size(); ++i) {
    if (!mask[i]) continue;
    sums.image += pixel_luminance(image, i);
    sums.reference += pixel_luminance(reference, i);
    ++sums.pixels;
  }
  return sums;
}

double ratio_of_sums(const LuminanceSums& sums) {
  if (sums.reference != 0.0) return sums.image / sums.reference;
  return sums.image == 0.0 ? 1.0 : std::numeric_limits<double>::infinity();
}

// docs/design.md §5: the denominator of a pixel's relative error, never below the
// floor, so near-black reference pixels are judged by an absolute error.
double relative_scale(double reference_luminance, double floor) { return std::max(reference_luminance, floor); }

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

std::unique_ptr<ToneMap> reference_tone_map(const ToneMapSettings& tone, const Image& reference,
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

double relative_within(const Image& image, const Image& reference, const std::vector<std::uint8_t>& mask,
                       double tolerance, double floor_fraction) {
  check_sizes(image, reference, mask);
  if (!std::isfinite(tolerance) || tolerance < 0.0) {
    throw std::invalid_argument("the tolerance of the relative norm must be a finite number >= 0, not " +
                                std::to_string(tolerance));
  }
  if (!std::isfinite(floor_fraction) || floor_fraction < 0.0) {
    throw std::invalid_argument("the floor of the relative norm must be a finite number >= 0, not " +
                                std::to_string(floor_fraction));
  }
  const LuminanceSums sums = luminance_sums(image, reference, mask);
  if (sums.pixels == 0) return 0.0;
  const double floor = floor_fraction * sums.reference / static_cast<double>(sums.pixels);
  std::size_t within = 0;
  for (std::size_t i = 0; i < mask.size(); ++i) {
    if (!mask[i]) continue;
    const double y = pixel_luminance(image, i), y_ref = pixel_luminance(reference, i);
    within += std::abs(y - y_ref) <= tolerance * relative_scale(y_ref, floor);
  }
  return 100.0 * static_cast<double>(within) / static_cast<double>(sums.pixels);
}

double mean_luminance_ratio(const Image& image, const Image& reference, const std::vector<std::uint8_t>& mask) {
  check_sizes(image, reference, mask);
  return ratio_of_sums(luminance_sums(image, reference, mask));
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
  const LuminanceSums sums = luminance_sums(image, reference, mask);
  m.rel_within_10 = relative_within(image, reference, mask, kNear);
  m.rel_within_15 = relative_within(image, reference, mask, kFar);
  m.mean_ratio = ratio_of_sums(sums);
  m.reference_mean_luminance = sums.reference / n;
  m.within_10 = 100.0 * static_cast<double>(near) / n;
  m.within_15 = 100.0 * static_cast<double>(far) / n;
  m.rmse = std::sqrt(squares / (3.0 * n));
  m.psnr_db = m.rmse > 0 ? -20.0 * std::log10(m.rmse) : std::numeric_limits<double>::infinity();
  m.relative_error = abs_reference > 0   ? abs_difference / abs_reference
                     : abs_difference > 0 ? std::numeric_limits<double>::infinity()
                                          : 0.0;
  return m;
}

Image difference_image(const Image& image, const Image& reference, const std::vector<std::uint8_t>& mask) {
  check_sizes(image, reference, mask);
  const LuminanceSums sums = luminance_sums(image, reference, mask);
  const double floor = sums.pixels ? kLuminanceFloor * sums.reference / static_cast<double>(sums.pixels) : 0.0;
  Image out(reference.width, reference.height);
  for (std::size_t i = 0; i < mask.size(); ++i) {
    if (!mask[i]) continue;
    const double y = pixel_luminance(image, i), y_ref = pixel_luminance(reference, i);
    const double difference = y - y_ref;
    const double scale = relative_scale(y_ref, floor);
    // The same comparison as relative_within, so the colours match its counts.
    float* p = &out.rgb[3 * i];
    if (std::abs(difference) <= kNear * scale) {
      // Dark grey even at zero error, so compared pixels stand out from the background.
      const double e = scale > 0 ? std::abs(difference) / scale : 0.0;
      const float g = static_cast<float>(0.15 + 0.6 * e / kNear);
      p[0] = p[1] = p[2] = g;
    } else if (std::abs(difference) <= kFar * scale) {
      p[0] = 1.0f, p[1] = 0.85f, p[2] = 0.0f;
    } else if (difference > 0) {
      p[0] = 1.0f, p[1] = 0.0f, p[2] = 0.0f;
    } else {
      p[0] = 0.0f, p[1] = 0.35f, p[2] = 1.0f;
    }
  }
  return out;
}

}  // namespace lhr
