#pragma once
// What a solution looks like from outside: per surface the conforming mesh
// with radiance and display colour at every vertex, the tone map chosen for
// the scene camera, and the Gouraud images (docs/design.md §1 outputs).

#include <memory>
#include <vector>

#include "io/image_io.hpp"
#include "io/mesh_io.hpp"
#include "mesh/hierarchy.hpp"
#include "mesh/scene.hpp"
#include "radiosity/tone_map.hpp"

namespace lhr {

struct SurfaceSolution {
  ConformingMesh mesh;
  std::vector<Rgb> radiance;  // per vertex of mesh.mesh
};

struct ToneMapChoice {
  enum class Kind { kTumblinRushmeier, kLinear } kind = Kind::kTumblinRushmeier;
  double world_adaptation = 0.0;  // 0: log-average luminance the camera sees
  double units_to_cd_m2 = 1.0;
  double display_max_cd_m2 = 100.0;
  double max_contrast = 100.0;
  double gamma = 2.2;
  double linear_white = 0.0;  // 0: the largest luminance the camera sees
};

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

// The tone map a choice stands for, given what the camera sees: the
// log-average luminance (TR adaptation default) and the brightest luminance
// (linear white default).
std::unique_ptr<ToneMap> make_tone_map(const ToneMapChoice& tone, double log_average, double brightest);

SolutionView make_solution_view(const std::vector<SurfaceSolution>& surfaces, const Camera& camera,
                                const ToneMapChoice& tone);

}  // namespace lhr
