// A program that knows lhr only through its installed package: loads the
// scene named on the command line, solves it coarsely with the linear solver
// and reports the surface count and mean radiance. Fails when the light does
// not reach the surfaces that do not emit, i.e. when nothing was transported.

#include <cstddef>
#include <cstdio>
#include <exception>

#include <lhr/io/scene_loader.hpp>
#include <lhr/mesh/initial_mesh.hpp>
#include <lhr/radiosity/linear_solver.hpp>
#include <lhr/radiosity/meshed_scene.hpp>

namespace {

double mean_channel(const lhr::Rgb& c) { return (c[0] + c[1] + c[2]) / 3.0; }

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s SCENE\n", argv[0]);
    return 2;
  }
  try {
    const lhr::LoadResult loaded = lhr::load_scene(argv[1]);
    lhr::MeshingOptions meshing;
    // Coarser than the default: this checks that the package links and runs,
    // not the accuracy of the solution.
    meshing.max_edge = 2.0 * lhr::default_max_edge(loaded.scene);
    lhr::MeshedScene model(loaded.scene, meshing);

    lhr::LinearOptions options;
    options.eps_link = 100.0;
    options.eps_pixel = 3.0;
    options.max_iterations = 5;
    lhr::LinearSolver solver(model, options);
    solver.solve();

    double sum_all = 0.0, sum_reflecting = 0.0;
    std::size_t n_all = 0, n_reflecting = 0;
    for (int s = 0; s < model.num_surfaces(); ++s) {
      const bool emitter = model.material(s).is_emitter();
      for (const lhr::Rgb& radiance : solver.vertex_radiance(s)) {
        sum_all += mean_channel(radiance);
        ++n_all;
        if (!emitter) {
          sum_reflecting += mean_channel(radiance);
          ++n_reflecting;
        }
      }
    }
    const double mean_all = n_all ? sum_all / n_all : 0.0;
    const double mean_reflecting = n_reflecting ? sum_reflecting / n_reflecting : 0.0;
    std::printf("surfaces %d\nmean radiance %g\nmean reflected radiance %g\n", model.num_surfaces(), mean_all,
                mean_reflecting);
    if (!(mean_reflecting > 0.0)) {
      std::fprintf(stderr, "%s: no light reached the non-emitting surfaces (mean radiance %g)\n", argv[1],
                   mean_reflecting);
      return 1;
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: %s\n", argv[1], e.what());
    return 1;
  }
  return 0;
}
