#pragma once
// How radiance becomes display values (docs/design.md §4 "Tone map M"): the
// one settings type that the scene file's "tone_map" block, the command-line
// flags, the Python keywords and the tone maps themselves share. A plain
// value of the scene contract; the maps live in radiosity/tone_map.

#include <optional>
#include <string_view>

namespace lhr {

enum class ToneMapKind { kTumblinRushmeier, kLinear };

// The names the scene file and the flags use: "tumblin-rushmeier", "linear".
const char* tone_map_kind_name(ToneMapKind kind);
std::optional<ToneMapKind> tone_map_kind_named(std::string_view name);

// Each field is the default until the scene file, then a flag or keyword,
// says otherwise.
struct ToneMapSettings {
  ToneMapKind kind = ToneMapKind::kTumblinRushmeier;
  double world_adaptation = 0.0;  // L_wa, scene radiance units; 0: the log-average luminance the camera sees
  double units_to_cd_m2 = 1.0;    // cd/m² per scene radiance unit
  double display_max_cd_m2 = 100.0;  // L_dmax
  double max_contrast = 100.0;       // C_max
  double gamma = 2.2;                // display gamma, both maps
  double white = 0.0;  // linear map: the luminance shown as white; 0: the brightest the camera sees
};

}  // namespace lhr
