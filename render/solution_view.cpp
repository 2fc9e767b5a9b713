#include "render/solution_view.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>

#include "render/gouraud.hpp"

namespace lhr {

double log_average_luminance(const Image& radiance, const std::vector<std::uint8_t>& mask) {
  // δ keeps black pixels from sending the mean to −∞ (Reinhard et al. 2002).
  constexpr double kDelta = 1e-6;
  double sum = 0.0;
  std::size_t count = 0;
  for (std::size_t i = 0; i < mask.size(); ++i) {
    if (!mask[i]) continue;
    const float* p = &radiance.rgb[3 * i];
    sum += std::log(kDelta + luminance(Rgb(p[0], p[1], p[2])));
    ++count;
  }
  return count ? std::exp(sum / static_cast<double>(count)) : 0.0;
}

std::string option_name(const std::string& keyword, OptionStyle style) {
  if (style == OptionStyle::kKeyword) return keyword;
  std::string flag = "--" + keyword;
  std::replace(flag.begin(), flag.end(), '_', '-');
  return flag;
}

ToneMapKind tone_map_kind(const std::string& name, OptionStyle style) {
  if (const std::optional<ToneMapKind> kind = tone_map_kind_named(name)) return *kind;
  throw std::invalid_argument(option_name("tone_map", style) + " must be tumblin-rushmeier or linear");
}

void check_tone_settings(const ToneMapSettings& tone, OptionStyle style) {
  if (!(tone.units_to_cd_m2 > 0) || !(tone.display_max_cd_m2 > 0) || !(tone.max_contrast > 1) ||
      !(tone.gamma > 0) || !(tone.world_adaptation >= 0) || !(tone.white >= 0)) {
    const auto name = [style](const char* keyword) { return option_name(keyword, style); };
    throw std::invalid_argument("tone map: " + name("units_to_cd") + ", " + name("display_max") + " and " +
                                name("gamma") + " must be positive, " + name("max_contrast") + " above 1, " +
                                name("adaptation") + " and " + name("white") + " zero or positive");
  }
}

SolutionView make_solution_view(const std::vector<SurfaceSolution>& surfaces, const Camera& camera,
                                const ToneMapSettings& tone) {
  SolutionView view;
  std::vector<const TriMesh*> meshes;
  std::vector<const std::vector<Rgb>*> radiance_sets;
  for (const SurfaceSolution& s : surfaces) {
    meshes.push_back(&s.mesh.mesh);
    radiance_sets.push_back(&s.radiance);
  }
  const PixelHits hits = trace_pixels(camera, meshes);
  view.hit_mask = hits.mask();
  view.radiance_image = shade_gouraud(hits, meshes, radiance_sets);

  double brightest = 0.0;
  for (std::size_t i = 0; i < view.hit_mask.size(); ++i) {
    if (!view.hit_mask[i]) continue;
    const float* p = &view.radiance_image.rgb[3 * i];
    brightest = std::max(brightest, luminance(Rgb(p[0], p[1], p[2])));
  }
  const double seen = log_average_luminance(view.radiance_image, view.hit_mask);
  view.tone_map = make_tone_map(tone, seen, brightest);
  if (tone.kind == ToneMapKind::kTumblinRushmeier) {
    view.world_adaptation = tone.world_adaptation > 0 ? tone.world_adaptation : (seen > 0 ? seen : 1.0);
  }

  std::vector<std::vector<Rgb>> display(surfaces.size());
  std::vector<const std::vector<Rgb>*> display_sets;
  for (std::size_t s = 0; s < surfaces.size(); ++s) {
    display[s].reserve(surfaces[s].radiance.size());
    for (const Rgb& r : surfaces[s].radiance) display[s].push_back(view.tone_map->display_rgb(r));
    display_sets.push_back(&display[s]);
    const std::size_t first = view.export_mesh.points.size();
    append_to_export(view.export_mesh, surfaces[s].mesh.mesh, surfaces[s].radiance);
    view.export_mesh.colours.resize(view.export_mesh.points.size());
    for (std::size_t v = 0; v < surfaces[s].radiance.size(); ++v) {
      view.export_mesh.colours[first + v] = view.tone_map->display_bytes(surfaces[s].radiance[v]);
    }
  }
  view.display_image = shade_gouraud(hits, meshes, display_sets);
  return view;
}

}  // namespace lhr
