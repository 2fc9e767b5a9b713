#pragma once
// Tone-map flags (reference, compare; `lhr solve` declares its own with its
// own help) and the settings they make. Precedence: a flag given on
// the command line, else the scene file's "tone_map" block, else the flag's
// default (docs/design.md §3, §4 "Tone map M").

#include <stdexcept>
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

// file_tone: the scene's settings (the defaults with its file's block over
// them), or nullptr without a scene. The flags' defaults are ToneMapSettings',
// so a flag left at its default keeps the file's value.
inline ToneMapSettings tone_settings_from(const po::variables_map& vm, const ToneMapSettings* file_tone) {
  try {
    ToneMapSettings tone = file_tone ? *file_tone : ToneMapSettings{};
    const auto given = [&](const char* flag, double& field) {
      if (!vm[flag].defaulted()) field = vm[flag].as<double>();
    };
    if (!vm["tone-map"].defaulted()) {
      tone.kind = tone_map_kind(vm["tone-map"].as<std::string>(), OptionStyle::kFlag);
    }
    given("adaptation", tone.world_adaptation);
    given("units-to-cd", tone.units_to_cd_m2);
    given("white", tone.white);
    given("display-max", tone.display_max_cd_m2);
    given("max-contrast", tone.max_contrast);
    given("gamma", tone.gamma);
    check_tone_settings(tone, OptionStyle::kFlag);
    return tone;
  } catch (const std::invalid_argument& e) {
    throw po::error(e.what());  // a usage error, like any bad flag
  }
}

}  // namespace lhr::app
