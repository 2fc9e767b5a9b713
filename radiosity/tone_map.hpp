#pragma once
// Tone mapping M: linear radiance -> display intensity in [0,1] (paper §4.1
// "Map", ref. 18; docs/design.md §4 "Tone map M"). Used by the receiver oracle, the
// PNG images and the exported vertex colours alike.

#include <array>
#include <cstdint>
#include <memory>
#include <string>

#include "mesh/tone_map_settings.hpp"
#include "mesh/types.hpp"

namespace lhr {

// Rec. 709 luminance of linear RGB.
inline double luminance(const Rgb& c) { return 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]; }

class ToneMap {
 public:
  virtual ~ToneMap() = default;
  // Display intensity of a world luminance (scene units), in [0,1], gamma applied.
  virtual double display(double world_luminance) const = 0;
  // Display colour: channels scaled by the luminance ratio, then gamma.
  virtual Rgb display_rgb(const Rgb& radiance) const = 0;
  virtual std::string describe() const = 0;
  std::array<std::uint8_t, 3> display_bytes(const Rgb& radiance) const;
};

// Tumblin–Rushmeier 1993 (paper ref. 18), with the constants of docs/design.md §4. The
// adaptation luminances are held to the range where the model cannot flatten or
// invert (at least ≈1.1·10⁻³ cd/m², see tone_map.cpp), so display() is monotone
// non-decreasing in the world luminance at every adaptation.
class TumblinRushmeierToneMap final : public ToneMap {
 public:
  // settings.world_adaptation must be resolved (positive): make_tone_map()
  // puts in the luminance the camera sees where the settings leave it 0.
  explicit TumblinRushmeierToneMap(const ToneMapSettings& settings);
  double display(double world_luminance) const override;
  Rgb display_rgb(const Rgb& radiance) const override;
  std::string describe() const override;
  // Display luminance in cd/m² before normalisation (exposed for tests).
  double display_luminance_cd_m2(double world_luminance) const;

 private:
  ToneMapSettings settings_;
  double exponent_ = 1.0;       // α(L_wa)/α(L_da)
  double log_multiplier_ = 0.0;  // (β(L_wa) − β(L_da))/α(L_da)
  double log_lamberts_per_unit_ = 0.0;
};

// Maps `white` to 1, linearly, then gamma.
class LinearToneMap final : public ToneMap {
 public:
  LinearToneMap(double white, double gamma = 2.2);
  double display(double world_luminance) const override;
  Rgb display_rgb(const Rgb& radiance) const override;
  std::string describe() const override;

 private:
  double white_;
  double gamma_;
};

// The tone map the settings stand for, given what the camera sees: the
// log-average luminance (the Tumblin–Rushmeier adaptation when the settings
// leave it 0) and the brightest luminance (the linear map's white likewise).
std::unique_ptr<ToneMap> make_tone_map(const ToneMapSettings& settings, double log_average, double brightest);

}  // namespace lhr
