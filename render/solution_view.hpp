#pragma once
// What a solution looks like from outside: per surface the conforming mesh
// with radiance and display colour at every vertex, the tone map chosen for
// the scene camera, and the Gouraud images (docs/design.md §1 outputs).

#include <memory>
#include <string>
#include <vector>

#include "mesh/export_mesh.hpp"
#include "mesh/hierarchy.hpp"
#include "mesh/image.hpp"
#include "mesh/scene.hpp"
#include "radiosity/tone_map.hpp"

namespace lhr {

struct SurfaceSolution {
  ConformingMesh mesh;
  std::vector<Rgb> radiance;  // per vertex of mesh.mesh
};

// How a check names a setting in its message: as a command-line flag
// ("--eps-pixel") or as a keyword of the Python module ("eps_pixel").
enum class OptionStyle { kFlag, kKeyword };

// keyword is the snake_case name ("max_links"); the flag is its kebab form.
std::string option_name(const std::string& keyword, OptionStyle style);

// "tumblin-rushmeier" or "linear"; anything else throws std::invalid_argument.
ToneMapKind tone_map_kind(const std::string& name, OptionStyle style);

// Throws std::invalid_argument naming the fields out of range.
void check_tone_settings(const ToneMapSettings& tone, OptionStyle style);

struct SolutionView {
  ExportMesh export_mesh;  // all surfaces, display colours and radiance
  Image radiance_image;    // linear radiance interpolated (EXR)
  Image display_image;     // display values interpolated (PNG), as the paper assumes
  std::vector<std::uint8_t> hit_mask;
  std::unique_ptr<ToneMap> tone_map;
  double world_adaptation = 0.0;
};

// exp(mean(log(δ + L))) over the pixels where a surface is seen.
double log_average_luminance(const Image& radiance, const std::vector<std::uint8_t>& mask);

SolutionView make_solution_view(const std::vector<SurfaceSolution>& surfaces, const Camera& camera,
                                const ToneMapSettings& tone);

}  // namespace lhr
