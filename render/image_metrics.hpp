#pragma once
// How close an image is to a reference (DESIGN §5 "Metrics"): the paper's
// norm (after Drettakis and Fiume) — the share of pixels whose display
// intensity differs from the reference's by at most 10 % and 15 % of the
// display range — plus RMSE and PSNR of the display values and the relative
// error of the linear radiance. Background pixels are excluded.
//
// Display values are the tone map's per-channel output in [0,1] (gamma
// applied), and a pixel's difference is the largest over its three channels:
// a pixel counts as within 10 % only if red, green and blue all are, so
// colour errors (colour bleeding) count as well as brightness errors.

#include <cstdint>
#include <memory>
#include <vector>

#include "io/image_io.hpp"
#include "radiosity/tone_map.hpp"
#include "render/solution_view.hpp"

namespace lhr {

struct ImageMetrics {
  std::size_t pixels = 0;         // pixels compared (non-background)
  double within_10 = 0.0;         // % of them with display difference ≤ 0.10
  double within_15 = 0.0;         // % of them with display difference ≤ 0.15
  double rmse = 0.0;              // RMS display difference over pixels and channels
  double psnr_db = 0.0;           // 20·log10(1/rmse); +inf when rmse = 0
  double max_difference = 0.0;    // largest display difference
  double relative_error = 0.0;    // Σ|a−b| / Σ|b| of linear radiance over pixels and channels
};

// Pixels where the reference is exactly 0 in all three channels are
// background (what a reference whose coverage mask is lost looks like).
std::vector<std::uint8_t> nonzero_mask(const Image& reference);

// The tone map a choice stands for when the reference is what the camera
// sees: the log-average and the brightest luminance over the masked
// reference pixels fill the defaults (as make_solution_view does for a
// solution), so an image and its reference are mapped alike.
std::unique_ptr<ToneMap> reference_tone_map(const ToneMapChoice& tone, const Image& reference,
                                            const std::vector<std::uint8_t>& mask);

// Both images go through the same tone map. mask: 1 = compare this pixel.
// Throws std::invalid_argument when the sizes differ.
ImageMetrics compare_images(const Image& image, const Image& reference, const std::vector<std::uint8_t>& mask,
                            const ToneMap& tone);

// A picture of where the image is off: background black; pixels within 10 %
// grey, brighter with the difference; within 15 % yellow; beyond, red.
Image difference_image(const Image& image, const Image& reference, const std::vector<std::uint8_t>& mask,
                       const ToneMap& tone);

}  // namespace lhr
