#pragma once
// Every radiosity method behind one face, for the checks that hold for all of
// them (tests/test_every_method.cpp): a method is run on a scene and read back
// through what those checks need. Everything particular to one solver lives in
// this file, so a third method, or a change to a solver's API, touches it alone.

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <ostream>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "mesh/initial_mesh.hpp"
#include "radiosity/classical_solver.hpp"
#include "radiosity/linear_solver.hpp"
#include "radiosity/meshed_scene.hpp"
#include "scene_fixtures.hpp"

namespace lhr::test {

enum class Method { kLinear, kClassical };

inline std::vector<Method> every_method() { return {Method::kLinear, Method::kClassical}; }

inline std::string method_label(Method method) {
  switch (method) {
    case Method::kLinear:
      return "linear";
    case Method::kClassical:
      return "classical";
  }
  throw std::logic_error("unknown method");
}

// How GoogleTest and ctest name a case's method.
inline void PrintTo(Method method, std::ostream* os) { *os << method_label(method); }

// A value a check chooses per method: `every` unless `except` names the method.
template <typename T>
struct PerMethod {
  T every;
  std::map<Method, T> except = {};
  const T& operator[](Method method) const {
    const auto it = except.find(method);
    return it == except.end() ? every : it->second;
  }
};

// How a check asks a method to solve; 0 leaves a knob at the method's default.
struct MethodSettings {
  double max_edge = 0.0;  // h of the initial mesh (required)
  double tolerance = 0.0;  // convergence
  // The method's own refinement threshold: linear ε_link, classical ε_BF.
  double eps = 0.0;
  int visibility_samples = 0;
  int max_iterations = 0;
  bool refine = true;  // false: no link is refined (every threshold out of reach)
  // Every leaf of surface `presplit_surface` split `presplit_levels` times
  // before the solve, for a method whose refinement would not make the
  // receiver fine enough by itself.
  int presplit_surface = -1;
  int presplit_levels = 0;
};

class SolverUnderTest {
 public:
  SolverUnderTest(Method method, Scene scene, const MethodSettings& settings)
      : method_(method), scene_(std::move(scene)) {
    MeshingOptions meshing;
    meshing.max_edge = settings.max_edge;
    model_ = std::make_unique<MeshedScene>(scene_, meshing);
    if (settings.presplit_surface >= 0) {
      SurfaceHierarchy& h = model_->hierarchy(settings.presplit_surface);
      for (int level = 0; level < settings.presplit_levels; ++level) {
        for (NodeId leaf : h.leaves()) h.split(leaf);
      }
    }
    switch (method) {
      case Method::kLinear:
        linear_ = std::make_unique<LinearSolver>(*model_, options_from(settings, &LinearOptions::eps_link));
        break;
      case Method::kClassical:
        classical_ = std::make_unique<ClassicalSolver>(*model_, options_from(settings, &ClassicalOptions::eps_bf));
        break;
    }
  }

  Method method() const { return method_; }
  const MeshedScene& model() const { return *model_; }

  void solve() {
    if (linear_) linear_->solve();
    if (classical_) classical_->solve();
  }

  // Radiance at every vertex of surface s's conforming mesh
  // (model().hierarchy(s).conforming_mesh()), in its vertex order: the
  // collocated values of the linear method, the area-weighted mean of the
  // leaves around each vertex for the constant elements of the classical one.
  std::vector<Rgb> vertex_radiance(int s) const {
    const ConformingMesh mesh = model_->hierarchy(s).conforming_mesh();
    return linear_ ? linear_->vertex_radiance(s, mesh) : classical_->vertex_radiance(s, mesh);
  }

  // The transport coefficients reaching surface s, summed at each of the
  // method's receiving points there (1 in a closed scene): every initial
  // vertex for the linear method, every leaf for the classical one.
  std::vector<double> row_sums(int s) const {
    std::vector<double> sums;
    const SurfaceHierarchy& h = model_->hierarchy(s);
    if (linear_) {
      for (VertexId v = 0; v < static_cast<VertexId>(h.num_vertices()); ++v) {
        if (h.vertex_level(v) == 0) sums.push_back(linear_->row_sum(s, v));
      }
    } else {
      for (NodeId leaf : h.leaves()) sums.push_back(classical_->row_sum(s, leaf));
    }
    return sums;
  }

  // Power absorbed by every surface, each method read in its own basis: the
  // linear interpolant of the vertex values (which needs ρ > 0 to recover the
  // irradiance: a black surface's share is missed), the gathered value of
  // each constant leaf.
  Rgb absorbed_power() const {
    if (linear_) {
      return test::absorbed_power(*model_, [&](int s) { return vertex_radiance(s); });
    }
    Rgb absorbed(0, 0, 0);
    for (int s = 0; s < model_->num_surfaces(); ++s) {
      const Material& m = model_->material(s);
      for (NodeId leaf : model_->hierarchy(s).leaves()) {
        const double a = model_->area(s, leaf);
        for (int c = 0; c < 3; ++c) {
          absorbed[c] += M_PI * a * (1.0 - m.reflectance[c]) * classical_->gathered(s, leaf)[c];
        }
      }
    }
    return absorbed;
  }

  // How far refinement went: links the linear method's shooter oracle
  // refined; for the classical method, which does not count them, links
  // beyond one per pair of surfaces.
  std::size_t refined_links() const {
    if (linear_) return linear_->stats().shooter_refinements;
    const auto n = static_cast<std::size_t>(model_->num_surfaces());
    return classical_->stats().links > n * n ? classical_->stats().links - n * n : 0;
  }

  int iterations() const { return linear_ ? linear_->stats().iterations : classical_->stats().iterations; }

  // The deepest level any surface's hierarchy reached.
  int max_level() const {
    int level = 0;
    for (int s = 0; s < model_->num_surfaces(); ++s) level = std::max(level, model_->hierarchy(s).max_level());
    return level;
  }

 private:
  // The settings every method has, and `eps` as the one named.
  template <typename Options>
  static Options options_from(const MethodSettings& settings, double Options::*eps) {
    Options options;
    if (settings.tolerance > 0) options.tolerance = settings.tolerance;
    if (settings.eps > 0) options.*eps = settings.eps;
    if (settings.visibility_samples > 0) options.visibility_samples = settings.visibility_samples;
    if (settings.max_iterations > 0) options.max_iterations = settings.max_iterations;
    if (!settings.refine) options.*eps = 1e9;
    if constexpr (std::is_same_v<Options, LinearOptions>) {
      if (!settings.refine) options.eps_pixel = 1e9;
    }
    return options;
  }

  Method method_;
  Scene scene_;  // the model keeps a pointer to it
  std::unique_ptr<MeshedScene> model_;
  std::unique_ptr<LinearSolver> linear_;
  std::unique_ptr<ClassicalSolver> classical_;
};

}  // namespace lhr::test
