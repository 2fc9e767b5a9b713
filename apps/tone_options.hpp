#pragma once
// Tone-map flags (reference, compare; `lhr solve` declares its own with its
// own help) and the choice they make. Precedence: a flag given on
// the command line, else the scene file's "tone_map" block, else the flag's
// default (docs/design.md §3, §4 "Tone map M").

#include <optional>
#include <string>

#include "apps/options.hpp"
#include "mesh/scene.hpp"
#include "render/solution_view.hpp"

namespace lhr::app {

inline void add_tone_map_options(po::options_description& options) {
  options.add_options()
      ("tone-map", po::value<std::string>()->default_value("tumblin-rushmeier"),
       "tumblin-rushmeier (paper ref. 18) or linear; the tone flags override the scene file's "
       "\"tone_map\" block, which overrides these defaults")
      ("adaptation", double_value(0.0),
       "world adaptation luminance for tumblin-rushmeier, scene units (0: log-average of the reference's "
       "non-background pixels)")
      ("units-to-cd", double_value(1.0), "cd/m^2 per scene radiance unit")
      ("white", double_value(0.0),
       "linear tone map: luminance shown as white (0: the reference's brightest pixel)")
      ("display-max", double_value(100.0),
       "tumblin-rushmeier: display's maximum luminance, cd/m^2")
      ("max-contrast", double_value(100.0), "tumblin-rushmeier: display's maximum contrast")
      ("gamma", double_value(2.2), "display gamma");
}

// file_tone: the scene file's block, or nullptr without a scene.
inline ToneMapChoice tone_choice_from(const po::variables_map& vm, const ToneMapSettings* file_tone) {
  const ToneMapSettings none;
  const ToneMapSettings& file = file_tone ? *file_tone : none;
  const auto pick = [&](const char* flag, const std::optional<double>& from_file) {
    return (!vm[flag].defaulted() || !from_file) ? vm[flag].as<double>() : *from_file;
  };
  const std::string name =
      (!vm["tone-map"].defaulted() || !file.kind) ? vm["tone-map"].as<std::string>() : *file.kind;
  if (name != "tumblin-rushmeier" && name != "linear") {
    throw po::error("--tone-map must be tumblin-rushmeier or linear");
  }
  ToneMapChoice tone;
  tone.kind = name == "linear" ? ToneMapChoice::Kind::kLinear : ToneMapChoice::Kind::kTumblinRushmeier;
  tone.world_adaptation = pick("adaptation", file.world_adaptation);
  tone.units_to_cd_m2 = pick("units-to-cd", file.units_to_cd_m2);
  tone.linear_white = pick("white", file.white);
  tone.display_max_cd_m2 = pick("display-max", file.display_max_cd_m2);
  tone.max_contrast = pick("max-contrast", file.max_contrast);
  tone.gamma = pick("gamma", file.gamma);
  if (!(tone.units_to_cd_m2 > 0) || !(tone.display_max_cd_m2 > 0) || !(tone.max_contrast > 1) ||
      !(tone.gamma > 0) || !(tone.world_adaptation >= 0) || !(tone.linear_white >= 0)) {
    throw po::error("tone map: --units-to-cd, --display-max and --gamma must be positive, --max-contrast above 1, "
                    "--adaptation and --white zero or positive");
  }
  return tone;
}

}  // namespace lhr::app
