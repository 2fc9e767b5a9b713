#include "render/solution.hpp"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>
#include <stdexcept>

#include "radiosity/memory_budget.hpp"
#include "radiosity/meshed_scene.hpp"
#include "radiosity/solver_frame.hpp"
#include "render/gouraud.hpp"

namespace lhr {

namespace {

nlohmann::json camera_json(const Camera& camera) {
  return {{"eye", {camera.eye[0], camera.eye[1], camera.eye[2]}},
          {"target", {camera.target[0], camera.target[1], camera.target[2]}},
          {"up", {camera.up[0], camera.up[1], camera.up[2]}},
          {"fov_y_deg", camera.fov_y_deg},
          {"width", camera.width},
          {"height", camera.height}};
}

struct MethodRun {
  nlohmann::json parameters, stats;
  bool budget_reached = false;
  bool memory_budget_reached = false;
};

// What both methods do once their options are set: solve, take each
// surface's conforming mesh with its radiance, and report the parameters and
// budgets they share beside their own.
template <class Solver, class Options>
MethodRun run_method(MeshedScene& model, const Options& options, nlohmann::json parameters,
                     std::vector<SurfaceSolution>& surfaces, const std::function<void(int, double)>& progress) {
  Solver solver(model, options);
  solver.solve(progress);
  for (int s = 0; s < model.num_surfaces(); ++s) {
    surfaces[s].mesh = model.hierarchy(s).conforming_mesh();
    surfaces[s].radiance = solver.vertex_radiance(s, surfaces[s].mesh);
  }
  const auto& st = solver.stats();
  MethodRun run;
  run.budget_reached = st.link_budget_reached;
  // docs/robustness.md, "Budgets": a shooter's first links are made whatever
  // the budget (without them its light would reach nothing), so the data can
  // end over it with no refinement ever refused.
  run.memory_budget_reached =
      st.memory_budget_reached || (options.max_bytes > 0 && st.bytes_total() > options.max_bytes);
  run.parameters = std::move(parameters);
  run.parameters.update({{"min_edge", options.min_edge > 0 ? options.min_edge : model.max_edge() / 32.0},
                         {"max_iterations", options.max_iterations},
                         {"tolerance", options.tolerance},
                         {"max_links", options.max_links},
                         {"max_bytes", options.max_bytes},
                         {"visibility_samples", options.visibility_samples}});
  st.write_json(run.stats);
  run.stats["memory_budget_reached"] = run.memory_budget_reached;
  return run;
}

MethodRun run_linear(MeshedScene& model, const SolveSettings& settings, std::vector<SurfaceSolution>& surfaces,
                     const std::function<void(int, double)>& progress) {
  LinearOptions options = settings.linear;
  // Importance and the oracle's adaptation come from what the camera sees.
  std::vector<const TriMesh*> initial;
  for (int s = 0; s < model.num_surfaces(); ++s) initial.push_back(&model.hierarchy(s).mesh());
  options.view = view_samples(settings.camera, initial);
  const ToneMapSettings tone = settings.tone;
  options.tone_map = [tone](double log_average, double brightest) {
    return make_tone_map(tone, log_average, brightest);
  };
  return run_method<LinearSolver>(model, options,
                                  {{"eps_pixel", options.eps_pixel},
                                   {"eps_link", options.eps_link},
                                   {"eps_vertex", options.eps_vertex},
                                   {"eps_power", options.eps_power},
                                   {"vis_threshold", options.vis_threshold},
                                   {"link_power", options.link_power}},
                                  surfaces, progress);
}

MethodRun run_classical(MeshedScene& model, const SolveSettings& settings, std::vector<SurfaceSolution>& surfaces,
                        const std::function<void(int, double)>& progress) {
  const ClassicalOptions& options = settings.classical;
  return run_method<ClassicalSolver>(model, options, {{"eps_bf", options.eps_bf}}, surfaces, progress);
}

}  // namespace

const char* method_name(SolveMethod method) { return method == SolveMethod::kLinear ? "linear" : "classical"; }

void check_solver_options(const SolveSettings& settings, OptionStyle style) {
  const auto fail = [style](const char* keyword, const std::string& requirement) {
    throw std::invalid_argument(option_name(keyword, style) + " must be " + requirement);
  };
  const LinearOptions& linear = settings.linear;
  const ClassicalOptions& classical = settings.classical;
  if (!(classical.eps_bf > 0)) fail("eps_bf", "positive");
  if (!(linear.eps_pixel > 0) || !(linear.eps_link > 0)) {
    throw std::invalid_argument(option_name("eps_pixel", style) + " and " + option_name("eps_link", style) +
                                " must be positive");
  }
  if (!(linear.eps_power > 0) || !std::isfinite(linear.eps_power)) fail("eps_power", "positive");
  if (!(linear.vis_threshold > 0)) fail("vis_threshold", "positive");
  if (!(linear.eps_vertex >= 0) || !std::isfinite(linear.eps_vertex)) fail("eps_vertex", "0 (off) or positive");
  if (!(linear.link_power >= 0)) fail("link_power", "zero or positive");
  // Both methods' options, whichever runs: a bad value is a mistake either way.
  for (const double min_edge : {linear.min_edge, classical.min_edge}) {
    if (!(min_edge >= 0)) fail("min_edge", "zero or positive");
  }
  for (const int max_iterations : {linear.max_iterations, classical.max_iterations}) {
    if (max_iterations < 1) fail("max_iterations", "at least 1");
  }
  for (const double tolerance : {linear.tolerance, classical.tolerance}) {
    if (!(tolerance > 0)) fail("tolerance", "positive");
  }
  for (const int samples : {linear.visibility_samples, classical.visibility_samples}) {
    if (samples < 1) fail("visibility_samples", "at least 1");
  }
}

void check_meshing_options(const MeshingOptions& meshing, OptionStyle style) {
  if (!(meshing.max_edge > 0.0) || !std::isfinite(meshing.max_edge)) {
    throw std::invalid_argument(option_name("max_edge", style) + " must be a positive number");
  }
  if (!(meshing.min_angle_deg > 0.0 && meshing.min_angle_deg <= 30.0)) {
    throw std::invalid_argument(option_name("min_angle", style) + " must be in (0, 30] degrees");
  }
}

namespace {

// The --max-memory of the method that runs.
std::size_t memory_budget(const SolveSettings& settings) {
  return settings.method == SolveMethod::kLinear ? settings.linear.max_bytes : settings.classical.max_bytes;
}

}  // namespace

void check_image_budget(const SolveSettings& settings, OptionStyle style) {
  const std::size_t machine = machine_memory_bytes();
  if (machine == 0) return;
  const std::size_t max_bytes = memory_budget(settings);
  const double pixels = static_cast<double>(settings.camera.width) * static_cast<double>(settings.camera.height);
  const double needed = pixels * static_cast<double>(kImageBytesPerPixel);
  const double beside = kBudgetPeakMargin * static_cast<double>(max_bytes);
  if (needed + beside <= static_cast<double>(machine)) return;
  std::ostringstream line;
  line << "a " << settings.camera.width << " x " << settings.camera.height << " image needs about "
       << format_bytes(static_cast<std::size_t>(std::min(needed, 1e18)));
  line << (max_bytes > 0 ? ", which beside a memory budget of " + format_bytes(max_bytes) + " is" : std::string(","));
  line << " more than the " << format_bytes(machine) << " this machine has: make the camera's width and height smaller";
  if (max_bytes > 0) line << " or lower " << option_name("max_memory", style);
  throw std::invalid_argument(line.str());
}

std::vector<std::string> scene_warnings(const Scene& scene) {
  for (const Material& m : scene.materials) {
    if (m.is_emitter()) return {};
  }
  return {"the scene has no emitter; the result is black"};
}

std::vector<std::string> solution_warnings(const SolveSettings& settings, const Solution& solution,
                                           OptionStyle style) {
  std::vector<std::string> warnings;
  if (solution.link_budget_reached) {
    warnings.push_back(option_name("max_links", style) + " reached; refinement stopped early");
  }
  const std::size_t max_bytes = memory_budget(settings);
  const std::size_t data = solution.stats.contains("bytes") ? solution.stats["bytes"].value("total", std::size_t{0}) : 0;
  const double left_out = solution.stats.value("power_left_out_for_memory", 0.0);
  if (left_out > 0) {
    std::ostringstream line;
    line << solution.stats.value("surfaces_left_out_for_memory", std::size_t{0}) << " surfaces holding "
         << std::setprecision(3) << 100.0 * left_out << " % of the emitted power never shot: their first links do not fit in "
         << option_name("max_memory", style) << " (" << format_bytes(max_bytes)
         << "), so the light they reflect is missing; raise it to keep that light";
    warnings.push_back(line.str());
  }
  if (max_bytes > 0 && data > max_bytes) {
    warnings.push_back("the radiosity data ended at " + format_bytes(data) + ", over " +
                       option_name("max_memory", style) + " (" + format_bytes(max_bytes) +
                       "): the first links of surfaces that emit (in the classical method, of every shooter) "
                       "are made whatever the budget, so that no light is dropped, and nothing was refined past it");
  } else if (solution.memory_budget_reached && !(left_out > 0)) {
    warnings.push_back(option_name("max_memory", style) + " reached; refinement stopped early");
  }
  // An iteration limit, not convergence, ends a solve whose light does not
  // die out (Kd = 1 in a closed scene, docs/robustness.md).
  const bool linear = settings.method == SolveMethod::kLinear;
  const int max_iterations = linear ? settings.linear.max_iterations : settings.classical.max_iterations;
  const double tolerance = linear ? settings.linear.tolerance : settings.classical.tolerance;
  const double final_change = solution.stats.value("final_change", 0.0);
  if (solution.stats.value("iterations", 0) >= max_iterations && !(final_change < tolerance)) {
    std::ostringstream line;
    line << "not converged after " << max_iterations << " iterations (largest change " << final_change
         << ", tolerance " << tolerance << "); the result is the last iteration's";
    warnings.push_back(line.str());
  }
  return warnings;
}

Solution solve_scene(const Scene& scene, const SolveSettings& settings,
                          const std::function<void(int, double)>& progress) {
  double seconds_meshing = 0.0, seconds_solve = 0.0, seconds_view = 0.0;
  PhaseTimer meshing(seconds_meshing);
  MeshedScene model(scene, settings.meshing);
  meshing.stop();

  std::vector<SurfaceSolution> surfaces(model.num_surfaces());
  PhaseTimer solving(seconds_solve);
  MethodRun run = settings.method == SolveMethod::kLinear ? run_linear(model, settings, surfaces, progress)
                                                          : run_classical(model, settings, surfaces, progress);
  solving.stop();

  PhaseTimer viewing(seconds_view);
  Solution out;
  out.view = make_solution_view(surfaces, settings.camera, settings.tone);
  out.view.export_mesh.colour_meaning =
      "display colour, tone-mapped " + out.view.tone_map->describe() + ", not linear";
  out.link_budget_reached = run.budget_reached;
  out.memory_budget_reached = run.memory_budget_reached;

  nlohmann::json& doc = out.stats;
  doc["scene"] = scene.source;
  doc["method"] = method_name(settings.method);
  run.parameters.update({{"max_edge", settings.meshing.max_edge},
                         {"min_angle_deg", settings.meshing.min_angle_deg},
                         {"tone_map", out.view.tone_map->describe()},
                         {"camera", camera_json(settings.camera)}});
  doc["parameters"] = run.parameters;
  doc["surfaces"] = model.num_surfaces();
  doc.update(run.stats);
  doc["exported_vertices"] = out.view.export_mesh.points.size();
  doc["exported_triangles"] = out.view.export_mesh.triangles.size();
  doc["world_adaptation"] = out.view.world_adaptation;
  viewing.stop();
  doc["seconds"].update({{"meshing", seconds_meshing}, {"solve", seconds_solve}, {"view", seconds_view}});
  return out;
}

}  // namespace lhr
