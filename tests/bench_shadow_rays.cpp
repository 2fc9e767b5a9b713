// Shadow rays per second on the Cornell box: one ray at a time against
// Embree's stream queries (RayScene::occluded on a batch). Not a test: run
// build/tests/bench_shadow_rays and record the result in BENCHMARKS.md.

#include <benchmark/benchmark.h>

#include "io/scene_loader.hpp"
#include "radiosity/ray_scene.hpp"
#include "radiosity/sampling.hpp"
#include "radiosity/scene_model.hpp"

namespace lhr {
namespace {

struct CornellRays {
  Scene scene;
  std::unique_ptr<SceneModel> model;
  std::vector<ShadowRay> rays;

  CornellRays() {
    scene = load_scene(std::string(LHR_SOURCE_DIR) + "/data/cornell/cornell.scene.json").scene;
    MeshingOptions meshing;
    meshing.max_edge = 48.0;
    model = std::make_unique<SceneModel>(scene, meshing);
    // Segments between random points of random surface pairs, as form-factor
    // visibility asks for them: a mix of clear and blocked rays.
    for (std::uint64_t i = 0; rays.size() < 65536; ++i) {
      const int a = static_cast<int>(mix_bits(i) % model->num_surfaces());
      const int b = static_cast<int>(mix_bits(i + 7919) % model->num_surfaces());
      if (a == b) continue;
      const auto pick = [&](int s, std::uint64_t key) {
        const auto& h = model->hierarchy(s);
        const NodeId n = static_cast<NodeId>(mix_bits(key) % h.num_roots());
        const TriangleSample t = stratified_triangle_samples(1, key).front();
        return model->rays().lift(at(model->triangle(s, n), t), model->normal(s, n));
      };
      rays.push_back({pick(a, sample_key(i, 1)), pick(b, sample_key(i, 2))});
    }
  }
};

const CornellRays& cornell() {
  static const CornellRays data;
  return data;
}

void BM_ShadowRaysOneAtATime(benchmark::State& state) {
  const CornellRays& c = cornell();
  std::size_t blocked = 0;
  for (auto _ : state) {
    for (const ShadowRay& r : c.rays) blocked += c.model->rays().occluded(r.from, r.to) ? 1 : 0;
  }
  benchmark::DoNotOptimize(blocked);
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * c.rays.size()));
}
BENCHMARK(BM_ShadowRaysOneAtATime)->Unit(benchmark::kMillisecond);

void BM_ShadowRaysStream(benchmark::State& state) {
  const CornellRays& c = cornell();
  std::vector<std::uint8_t> blocked(c.rays.size());
  for (auto _ : state) {
    c.model->rays().occluded(c.rays, blocked);
    benchmark::DoNotOptimize(blocked.data());
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * c.rays.size()));
}
BENCHMARK(BM_ShadowRaysStream)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace lhr

BENCHMARK_MAIN();
