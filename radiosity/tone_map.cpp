#include "radiosity/tone_map.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace lhr {

namespace {

// TR93 works in lamberts: 1 L = 10⁴/π cd/m².
constexpr double kCdPerLambert = 1e4 / M_PI;

double alpha(double lamberts) { return 0.4 * std::log10(lamberts) + 2.92; }
double beta(double lamberts) {
  const double l = std::log10(lamberts);
  return -0.4 * l * l - 2.584 * l + 2.0208;
}

double apply_gamma(double v, double gamma) { return std::pow(std::clamp(v, 0.0, 1.0), 1.0 / gamma); }

std::uint8_t to_byte(double v) { return static_cast<std::uint8_t>(std::lround(255.0 * std::clamp(v, 0.0, 1.0))); }

}  // namespace

std::array<std::uint8_t, 3> ToneMap::display_bytes(const Rgb& radiance) const {
  const Rgb d = display_rgb(radiance);
  return {to_byte(d[0]), to_byte(d[1]), to_byte(d[2])};
}

TumblinRushmeierToneMap::TumblinRushmeierToneMap(const TumblinRushmeierParams& p) : p_(p) {
  if (!(p.world_adaptation > 0) || !(p.units_to_cd_m2 > 0) || !(p.display_max_cd_m2 > 0) ||
      !(p.max_contrast > 1) || !(p.gamma > 0) || !std::isfinite(p.world_adaptation)) {
    throw std::invalid_argument(
        "Tumblin-Rushmeier tone map: adaptation, unit scale, display maximum and gamma must be positive and "
        "the maximum contrast above 1");
  }
  const double l_wa = p.world_adaptation * p.units_to_cd_m2 / kCdPerLambert;
  const double l_da = p.display_max_cd_m2 / std::sqrt(p.max_contrast) / kCdPerLambert;
  exponent_ = alpha(l_wa) / alpha(l_da);
  log_multiplier_ = (beta(l_wa) - beta(l_da)) / alpha(l_da);
}

double TumblinRushmeierToneMap::display_luminance_cd_m2(double world_luminance) const {
  if (!(world_luminance > 0)) return 0.0;
  const double l_w = world_luminance * p_.units_to_cd_m2 / kCdPerLambert;
  const double l_d = std::pow(l_w, exponent_) * std::pow(10.0, log_multiplier_);
  return l_d * kCdPerLambert;
}

double TumblinRushmeierToneMap::display(double world_luminance) const {
  const double v = display_luminance_cd_m2(world_luminance) / p_.display_max_cd_m2 - 1.0 / p_.max_contrast;
  return apply_gamma(v, p_.gamma);
}

Rgb TumblinRushmeierToneMap::display_rgb(const Rgb& radiance) const {
  const double y = luminance(radiance);
  if (!(y > 0)) return Rgb(0, 0, 0);
  const double scale = display_luminance_cd_m2(y) / (y * p_.display_max_cd_m2);
  const double offset = 1.0 / p_.max_contrast;
  Rgb out;
  for (int k = 0; k < 3; ++k) out[k] = apply_gamma(radiance[k] * scale - offset, p_.gamma);
  return out;
}

std::string TumblinRushmeierToneMap::describe() const {
  std::ostringstream s;
  s << "tumblin-rushmeier (world adaptation " << p_.world_adaptation << ", display max " << p_.display_max_cd_m2
    << " cd/m2, contrast " << p_.max_contrast << ", gamma " << p_.gamma << ")";
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

}  // namespace lhr
