#pragma once
// One solve of a scene, from meshing to the Gouraud view, with either method:
// what `lhr solve` writes and what `lhr bench` sweeps (docs/design.md §1 outputs).

#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "mesh/initial_mesh.hpp"
#include "mesh/scene.hpp"
#include "radiosity/classical_solver.hpp"
#include "radiosity/linear_solver.hpp"
#include "render/solution_view.hpp"

namespace lhr {

enum class SolveMethod { kLinear, kClassical };

const char* method_name(SolveMethod method);

struct SolveSettings {
  SolveMethod method = SolveMethod::kLinear;
  MeshingOptions meshing;
  LinearOptions linear;  // its view and tone map are filled from `camera` and `tone`
  ClassicalOptions classical;
  ToneMapSettings tone;
  Camera camera;
};

struct Solution {
  SolutionView view;
  // stats.json: method, parameters, sizes, bytes, seconds per phase. The
  // "seconds" object and peak memory vary from run to run; nothing else does.
  nlohmann::json stats;
  bool link_budget_reached = false;    // refinement stopped at max_links
  bool memory_budget_reached = false;  // refinement stopped at max_bytes
};

// Each throws std::invalid_argument naming the first setting out of range,
// as `style` names settings. The solver options can be checked before the
// scene is read; meshing and tone depend on it.
void check_solver_options(const SolveSettings& settings, OptionStyle style);
void check_meshing_options(const MeshingOptions& meshing, OptionStyle style);
// The camera's image against the machine's memory beside the radiosity
// data's budget (docs/robustness.md, "Budgets"): a view that cannot fit is
// refused before the work starts, not found out by the allocator.
void check_image_budget(const SolveSettings& settings, OptionStyle style);

// What an image costs a solve per pixel, bytes (the view's samples, the
// radiance and display images, the files' buffers), rounded up from peak
// resident memory at 512², 2048² and 4096² (43–49 bytes).
inline constexpr std::size_t kImageBytesPerPixel = 64;

// What to tell the user before solving (no emitter: the result is black) and
// after (a budget stopped refinement, the iteration limit came before
// convergence), one line each without a prefix.
std::vector<std::string> scene_warnings(const Scene& scene);
std::vector<std::string> solution_warnings(const SolveSettings& settings, const Solution& solution,
                                           OptionStyle style);

// progress(iteration, largest change) after each solver iteration.
Solution solve_scene(const Scene& scene, const SolveSettings& settings,
                          const std::function<void(int, double)>& progress = {});

}  // namespace lhr
