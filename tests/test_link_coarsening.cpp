// Coarsening links (docs/design.md, "Coarsening links"): a vertex's links to
// all the children of a shooter element merge back into one link when the
// shooter oracle would keep it. The truth is the closed form of a light over
// a receiver with nothing between them: the receiver's radiance is ρ Le F,
// F from Lambert's formula (test::lambert_form_factor, apart from
// radiosity/form_factor).

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <string>

#include "radiosity/linear_solver.hpp"
#include "radiosity/meshed_scene.hpp"
#include "radiosity/tone_map.hpp"
#include "scene_fixtures.hpp"

namespace lhr {
namespace {

constexpr double kRho = 0.7;
constexpr double kLe = 100.0;

struct Outcome {
  std::size_t links = 0;
  std::size_t coarsenings = 0;
  double largest_cut_error = 0.0;  // |Σ_links unoccluded − F| / F at a graph vertex
  double mean_error = 0.0;         // relative, the receiver's vertices against ρ Le F
  double largest_error = 0.0;
};

Outcome solve(bool coarsen) {
  constexpr double kSide = 0.6, kHeight = 0.3;
  const Scene scene = test::emitter_over_receiver(kSide, kHeight, kRho, kLe);
  const double lo = 0.5 - kSide / 2, hi = 0.5 + kSide / 2;
  const std::array<Vec3, 4> light{Vec3(lo, lo, kHeight), Vec3(lo, hi, kHeight), Vec3(hi, hi, kHeight),
                                  Vec3(hi, lo, kHeight)};
  MeshingOptions meshing;
  meshing.max_edge = 0.25;
  MeshedScene model(scene, meshing);
  LinearOptions options;
  options.min_edge = 1e-3;
  // A camera close over one corner of the receiver: the links opened for
  // the nodes it sees are more than the nodes beside them need, and the
  // vertices a split makes start from their neighbour's links (measured:
  // 32 286 links kept, 3 645 coarsened).
  options.view = test::view_from(model, Vec3(0.15, 0.15, 0.25), Vec3(0.1, 0.1, 0.0), Vec3(0, 1, 0), 50.0, 96, 96);
  const ToneMapSettings tone;
  options.tone_map = [tone](double log_average, double brightest) {
    return make_tone_map(tone, log_average, brightest);
  };
  options.coarsen_links = coarsen;
  LinearSolver solver(model, options);
  solver.solve();

  int receiver = -1;
  for (int s = 0; s < model.num_surfaces(); ++s) {
    if (scene.surfaces[s].name.rfind("receiver", 0) == 0) receiver = s;
  }
  EXPECT_GE(receiver, 0);
  const Vec3 up(0, 0, 1);
  const SurfaceHierarchy& h = model.hierarchy(receiver);
  Outcome out;
  out.links = solver.stats().links;
  out.coarsenings = solver.stats().shooter_coarsenings;
  for (const InteractionGraph& g : solver.graphs()) {
    if (g.receiver_surface() != receiver) continue;
    for (int i = 0; i < static_cast<int>(g.num_vertices()); ++i) {
      const double f = test::lambert_form_factor(h.point(g.vertex(i)), up, light);
      out.largest_cut_error = std::max(out.largest_cut_error, std::abs(g.unoccluded(i) - f) / f);
    }
  }
  const std::vector<Rgb>& radiance = solver.vertex_radiance(receiver);
  for (std::size_t v = 0; v < radiance.size(); ++v) {
    const double truth = kRho * kLe * test::lambert_form_factor(h.point(static_cast<VertexId>(v)), up, light);
    const double error = std::abs(luminance(radiance[v]) - truth) / truth;
    out.mean_error += error / static_cast<double>(radiance.size());
    out.largest_error = std::max(out.largest_error, error);
  }
  return out;
}

TEST(LinkCoarsening, MergedLinksStillCoverTheWholeShooterAndKeepTheAnswer) {
  const Outcome fine = solve(false);
  const Outcome coarse = solve(true);
  RecordProperty("links_kept", std::to_string(fine.links));
  RecordProperty("links_coarsened", std::to_string(coarse.links));
  EXPECT_EQ(fine.coarsenings, 0u);
  EXPECT_GT(coarse.coarsenings, 0u) << "nothing was merged: the test sees nothing";
  EXPECT_LT(coarse.links, fine.links);
  // Every vertex's links are still one complete cut of the light: their
  // unoccluded form factors add up to the whole light's.
  EXPECT_LT(coarse.largest_cut_error, 1e-4);
  EXPECT_LT(fine.largest_cut_error, 1e-4);
  // Nothing hides the light and it is uniform, so any complete cut gives
  // the closed form: a merge that lost or doubled a child's share, or
  // weighed a corner wrongly, would show here. (Under occlusion the merged
  // coefficients are the children's own, recombined exactly:
  // TriangleTransport.FourChildrenMergedGiveTheParentsIntegralOfEachHat.)
  EXPECT_LT(coarse.largest_error, 1e-4) << "uncoarsened: " << fine.largest_error;
  EXPECT_LT(fine.largest_error, 1e-4);
}

}  // namespace
}  // namespace lhr
