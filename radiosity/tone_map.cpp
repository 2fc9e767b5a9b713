#include "radiosity/tone_map.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace lhr {

namespace {

// TR93 works in lamberts: 1 L = 10⁴/π cd/m².
constexpr double kCdPerLambert = 1e4 / M_PI;

// The range of adaptation luminances, as log10 lamberts, where TR93's fitted
// α(x) = 0.4x + 2.92 and β(x) = −0.4x² − 2.584x + 2.0208 (docs/design.md §4) describe
// vision. TR93 reads log10 B = α(x_a)·x + β(x_a) as the brightness of luminance x
// seen adapted to x_a (Stevens' brightness functions): adapting to more light
// must dim the adapting luminance itself, ∂/∂x_a = 0.4x_a + β'(x_a) =
// −0.4x_a − 2.584 ≤ 0, i.e. x_a ≥ −2.584/0.4 = −6.46 (≈1.1·10⁻³ cd/m²). Below it β
// rises faster than α·x falls, and from −7.3 (≈1.6·10⁻⁴ cd/m²) α ≤ 0, so the map's
// exponent α(L_wa)/α(L_da) reaches zero and then inverts it. At −6.46, α = 0.336,
// so the exponent stays positive. β's own vertex (x = −3.23, ≈1.9 cd/m²) is no
// bound: there β's rise only offsets the fall of α·x (α(x)·x + β(x) = 0.336x +
// 2.0208 is linear), and clamping at it would black out every interior adapted
// below 1.9 cd/m², the default Cornell box among them. Above,
// α rises and β falls without turning back, so there is no upper bound; the map
// is evaluated in logarithms so that extreme luminances stay finite.
constexpr double kMinAdaptationLog10Lamberts = -2.584 / 0.4;

double adaptation_log10_lamberts(double log10_cd_m2) {
  return std::max(log10_cd_m2 - std::log10(kCdPerLambert), kMinAdaptationLog10Lamberts);
}

double alpha(double log10_lamberts) { return 0.4 * log10_lamberts + 2.92; }
double beta(double log10_lamberts) {
  const double x = log10_lamberts;
  return -0.4 * x * x - 2.584 * x + 2.0208;
}

double apply_gamma(double v, double gamma) { return std::pow(std::clamp(v, 0.0, 1.0), 1.0 / gamma); }

std::uint8_t to_byte(double v) { return static_cast<std::uint8_t>(std::lround(255.0 * std::clamp(v, 0.0, 1.0))); }

}  // namespace

std::array<std::uint8_t, 3> ToneMap::display_bytes(const Rgb& radiance) const {
  const Rgb d = display_rgb(radiance);
  return {to_byte(d[0]), to_byte(d[1]), to_byte(d[2])};
}

TumblinRushmeierToneMap::TumblinRushmeierToneMap(const ToneMapSettings& p) : settings_(p) {
  const bool finite = std::isfinite(p.world_adaptation) && std::isfinite(p.units_to_cd_m2) &&
                      std::isfinite(p.display_max_cd_m2) && std::isfinite(p.max_contrast) && std::isfinite(p.gamma);
  if (!finite || !(p.world_adaptation > 0) || !(p.units_to_cd_m2 > 0) || !(p.display_max_cd_m2 > 0) ||
      !(p.max_contrast > 1) || !(p.gamma > 0)) {
    throw std::invalid_argument(
        "Tumblin-Rushmeier tone map: adaptation, unit scale, display maximum and gamma must be positive and finite "
        "and the maximum contrast above 1");
  }
  // Logarithms first: world_adaptation × units_to_cd_m2 may overflow or underflow.
  const double x_wa = adaptation_log10_lamberts(std::log10(p.world_adaptation) + std::log10(p.units_to_cd_m2));
  const double x_da = adaptation_log10_lamberts(std::log10(p.display_max_cd_m2 / std::sqrt(p.max_contrast)));
  exponent_ = alpha(x_wa) / alpha(x_da);
  log_multiplier_ = (beta(x_wa) - beta(x_da)) / alpha(x_da);
  log_lamberts_per_unit_ = std::log10(p.units_to_cd_m2) - std::log10(kCdPerLambert);
}

double TumblinRushmeierToneMap::display_luminance_cd_m2(double world_luminance) const {
  if (!(world_luminance > 0)) return 0.0;
  // docs/design.md §4: log10 L_d = (α(L_wa)/α(L_da))·log10 L_w + (β(L_wa) − β(L_da))/α(L_da), in lamberts;
  // over- or underflow of 10^x gives +inf or 0, never NaN.
  const double x_w = std::log10(world_luminance) + log_lamberts_per_unit_;
  return std::pow(10.0, exponent_ * x_w + log_multiplier_) * kCdPerLambert;
}

double TumblinRushmeierToneMap::display(double world_luminance) const {
  const double v =
      display_luminance_cd_m2(world_luminance) / settings_.display_max_cd_m2 - 1.0 / settings_.max_contrast;
  return apply_gamma(v, settings_.gamma);
}

Rgb TumblinRushmeierToneMap::display_rgb(const Rgb& radiance) const {
  // Channel ratios are taken against the largest channel so that huge radiances
  // cannot turn them into inf/inf; negative and NaN channels show as black.
  Rgb unit(0, 0, 0);
  double largest = 0.0;
  for (int k = 0; k < 3; ++k) {
    unit[k] = radiance[k] > 0 ? std::min(radiance[k], std::numeric_limits<double>::max()) : 0.0;
    largest = std::max(largest, unit[k]);
  }
  if (!(largest > 0)) return Rgb(0, 0, 0);
  for (int k = 0; k < 3; ++k) unit[k] /= largest;
  const double y_unit = luminance(unit);
  const double shown = display_luminance_cd_m2(largest * y_unit) / settings_.display_max_cd_m2;
  const double offset = 1.0 / settings_.max_contrast;
  Rgb out;
  for (int k = 0; k < 3; ++k) {
    out[k] = unit[k] > 0 ? apply_gamma(unit[k] / y_unit * shown - offset, settings_.gamma) : 0.0;
  }
  return out;
}

std::string TumblinRushmeierToneMap::describe() const {
  std::ostringstream s;
  s << "tumblin-rushmeier (world adaptation " << settings_.world_adaptation << ", display max "
    << settings_.display_max_cd_m2 << " cd/m2, contrast " << settings_.max_contrast << ", gamma " << settings_.gamma
    << ")";
  return s.str();
}

LinearToneMap::LinearToneMap(double white, double gamma) : white_(white), gamma_(gamma) {
  if (!(white > 0) || !std::isfinite(white) || !(gamma > 0)) {
    throw std::invalid_argument("linear tone map: white and gamma must be positive");
  }
}

double LinearToneMap::display(double world_luminance) const { return apply_gamma(world_luminance / white_, gamma_); }

Rgb LinearToneMap::display_rgb(const Rgb& radiance) const {
  Rgb out;
  for (int k = 0; k < 3; ++k) out[k] = apply_gamma(radiance[k] / white_, gamma_);
  return out;
}

std::string LinearToneMap::describe() const {
  std::ostringstream s;
  s << "linear (white " << white_ << ", gamma " << gamma_ << ")";
  return s.str();
}

std::unique_ptr<ToneMap> make_tone_map(const ToneMapSettings& settings, double log_average, double brightest) {
  if (settings.kind == ToneMapKind::kLinear) {
    const double white = settings.white > 0 ? settings.white : brightest;
    return std::make_unique<LinearToneMap>(white > 0 ? white : 1.0, settings.gamma);
  }
  ToneMapSettings resolved = settings;
  if (!(resolved.world_adaptation > 0)) resolved.world_adaptation = log_average;
  if (!(resolved.world_adaptation > 0)) resolved.world_adaptation = 1.0;  // a black view: any adaptation shows black
  return std::make_unique<TumblinRushmeierToneMap>(resolved);
}

}  // namespace lhr
