#pragma once
// How close an image is to a reference (docs/design.md §5 "How accuracy is judged").
//
// Primary: the relative norm on linear luminance. The truth is radiance, so
// a pixel is within t when |Y − Y_ref| ≤ t · max(Y_ref, f · mean Y_ref),
// Y the Rec. 709 luminance of the linear RGB, mean Y_ref over the compared
// pixels and the floor f = 1 % (near-black pixels would otherwise count a
// tiny absolute error as a huge relative one). The mean ratio
// mean Y / mean Y_ref reads a global bias directly (1.05: 5 % too bright).
//
// Secondary: the paper's norm (after Drettakis and Fiume) — the share of
// pixels whose display intensity differs from the reference's by at most
// 10 % and 15 % of the display range — plus RMSE and PSNR of the display
// values and the relative error of the linear radiance. Display values are
// the tone map's per-channel output in [0,1] (gamma applied), and a pixel's
// difference is the largest over its three channels. With a dim tone map
// every method passes the display norm, so it cannot rank methods or catch a
// bias (docs/design.md §5); it is kept to compare with the paper's figures.
//
// Background pixels (mask 0) are left out of every figure.

#include <cstdint>
#include <memory>
#include <vector>

#include "mesh/image.hpp"
#include "radiosity/tone_map.hpp"
#include "render/solution_view.hpp"

namespace lhr {

// docs/design.md §5: the floor of the relative norm, a fraction of mean Y_ref.
constexpr double kLuminanceFloor = 0.01;

struct ImageMetrics {
  std::size_t pixels = 0;  // pixels compared (non-background)
  // Primary, linear luminance.
  double rel_within_10 = 0.0;  // % of them with |Y − Y_ref| ≤ 0.10 · max(Y_ref, floor)
  double rel_within_15 = 0.0;  // % of them with |Y − Y_ref| ≤ 0.15 · max(Y_ref, floor)
  double mean_ratio = 0.0;     // mean Y / mean Y_ref; 1 when both are 0, +inf when only Y_ref's is
  double reference_mean_luminance = 0.0;  // mean Y_ref
  // Secondary, the paper's display-value norm and its companions.
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
std::unique_ptr<ToneMap> reference_tone_map(const ToneMapSettings& tone, const Image& reference,
                                            const std::vector<std::uint8_t>& mask);

// The relative norm: % of masked pixels with
// |Y − Y_ref| ≤ tolerance · max(Y_ref, floor_fraction · mean Y_ref).
// 0 when no pixel is masked. Throws std::invalid_argument when the sizes
// differ or tolerance or floor_fraction is negative or not finite.
double relative_within(const Image& image, const Image& reference, const std::vector<std::uint8_t>& mask,
                       double tolerance, double floor_fraction = kLuminanceFloor);

// mean Y / mean Y_ref over the masked pixels (1 when both are 0, +inf when
// only the reference's is). Throws std::invalid_argument when the sizes differ.
double mean_luminance_ratio(const Image& image, const Image& reference, const std::vector<std::uint8_t>& mask);

// Every figure above. The display figures take both images through the same
// tone map. mask: 1 = compare this pixel. Throws std::invalid_argument when
// the sizes differ.
ImageMetrics compare_images(const Image& image, const Image& reference, const std::vector<std::uint8_t>& mask,
                            const ToneMap& tone);

// A picture of the relative luminance error e = (Y − Y_ref) / max(Y_ref,
// floor): background black; |e| ≤ 10 % grey, brighter with |e|; ≤ 15 %
// yellow; beyond, red where the image is too bright and blue where it is
// too dark. Throws std::invalid_argument when the sizes differ.
Image difference_image(const Image& image, const Image& reference, const std::vector<std::uint8_t>& mask);

}  // namespace lhr
