#include "mesh/tone_map_settings.hpp"

namespace lhr {

const char* tone_map_kind_name(ToneMapKind kind) {
  return kind == ToneMapKind::kLinear ? "linear" : "tumblin-rushmeier";
}

std::optional<ToneMapKind> tone_map_kind_named(std::string_view name) {
  if (name == "tumblin-rushmeier") return ToneMapKind::kTumblinRushmeier;
  if (name == "linear") return ToneMapKind::kLinear;
  return std::nullopt;
}

}  // namespace lhr
