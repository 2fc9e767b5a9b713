// Shadow rays per second on the Cornell box, for every way RayCaster can hand
// a batch to Embree (one ray at a time, the rtcOccluded1M stream, packets of
// 4, 8 and 16), on two sets of rays: random segments between surfaces, in
// one batch, and the batches the solvers cast, the 16 rays of one link
// between stratified samples of two elements. Not a test: run
// bench_shadow_rays from the build directory and record the result in
// BENCHMARKS.md.

#include <benchmark/benchmark.h>

#include <span>

#include "io/scene_loader.hpp"
#include "radiosity/ray_caster.hpp"
#include "radiosity/sampling.hpp"
#include "radiosity/meshed_scene.hpp"

namespace lhr {
namespace {

constexpr std::size_t kRays = 65536;
constexpr int kLinkSide = 4;  // k: a link casts k² rays, as with the default --visibility-samples
constexpr std::size_t kLinkRays = kLinkSide * kLinkSide;

struct CornellRays {
  Scene scene;
  std::unique_ptr<MeshedScene> model;
  std::vector<ShadowRay> random;  // one batch
  std::vector<ShadowRay> links;   // kLinkRays per batch

  CornellRays() {
    scene = load_scene(std::string(LHR_SOURCE_DIR) + "/data/cornell/cornell.scene.json").scene;
    MeshingOptions meshing;
    meshing.max_edge = 48.0;
    model = std::make_unique<MeshedScene>(scene, meshing);
    const auto lifted = [&](int s, NodeId n, const TriangleSample& t) {
      return model->rays().lift(at(model->triangle(s, n), t), model->normal(s, n));
    };
    // Segments between random points of random surface pairs: a mix of
    // clear and blocked rays.
    for (std::uint64_t i = 0; random.size() < kRays; ++i) {
      const int a = static_cast<int>(mix_bits(i) % model->num_surfaces());
      const int b = static_cast<int>(mix_bits(i + 7919) % model->num_surfaces());
      if (a == b) continue;
      const auto pick = [&](int s, std::uint64_t key) {
        const NodeId n = static_cast<NodeId>(mix_bits(key) % model->hierarchy(s).num_roots());
        return lifted(s, n, stratified_triangle_samples(1, key).front());
      };
      random.push_back({pick(a, sample_key(i, 1)), pick(b, sample_key(i, 2))});
    }
    // Links between random initial triangles of two surfaces that face each
    // other: stratified samples on both, paired in order.
    for (std::uint64_t i = 0; links.size() < kRays; ++i) {
      const int a = static_cast<int>(mix_bits(sample_key(i, 3)) % model->num_surfaces());
      const int b = static_cast<int>(mix_bits(sample_key(i, 4)) % model->num_surfaces());
      if (a == b) continue;
      const NodeId na = static_cast<NodeId>(mix_bits(sample_key(i, 5)) % model->hierarchy(a).num_roots());
      const NodeId nb = static_cast<NodeId>(mix_bits(sample_key(i, 6)) % model->hierarchy(b).num_roots());
      const Vec3 d = model->centroid(b, nb) - model->centroid(a, na);
      if (!(OpenMesh::dot(model->normal(a, na), d) > 0 && OpenMesh::dot(model->normal(b, nb), d) < 0)) continue;
      const auto sa = stratified_triangle_samples(kLinkSide, sample_key(i, 7));
      const auto sb = stratified_triangle_samples(kLinkSide, sample_key(i, 8));
      for (std::size_t k = 0; k < kLinkRays; ++k) links.push_back({lifted(a, na, sa[k]), lifted(b, nb, sb[k])});
    }
  }
};

const CornellRays& cornell() {
  static const CornellRays data;
  return data;
}

const char* query_name(ShadowQuery q) {
  switch (q) {
    case ShadowQuery::kSingle: return "rtcOccluded1";
    case ShadowQuery::kStream: return "rtcOccluded1M";
    case ShadowQuery::kPacket4: return "rtcOccluded4";
    case ShadowQuery::kPacket8: return "rtcOccluded8";
    case ShadowQuery::kPacket16: return "rtcOccluded16";
  }
  return "?";
}

void BM_RandomRaysOneBatch(benchmark::State& state) {
  const CornellRays& c = cornell();
  const auto query = static_cast<ShadowQuery>(state.range(0));
  state.SetLabel(query_name(query));
  std::vector<std::uint8_t> blocked(c.random.size());
  for (auto _ : state) {
    c.model->rays().occluded(c.random, blocked, query);
    benchmark::DoNotOptimize(blocked.data());
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * c.random.size()));
}

// Batches of one link's size: `links` are coherent within a batch, `random` not.
void batches(benchmark::State& state, const std::vector<ShadowRay>& rays) {
  const CornellRays& c = cornell();
  const auto query = static_cast<ShadowQuery>(state.range(0));
  state.SetLabel(query_name(query));
  std::vector<std::uint8_t> blocked(rays.size());
  const std::span<const ShadowRay> all(rays);
  const std::span<std::uint8_t> out(blocked);
  for (auto _ : state) {
    for (std::size_t first = 0; first < all.size(); first += kLinkRays) {
      c.model->rays().occluded(all.subspan(first, kLinkRays), out.subspan(first, kLinkRays), query);
    }
    benchmark::DoNotOptimize(blocked.data());
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * rays.size()));
}

void BM_LinkBatches(benchmark::State& state) { batches(state, cornell().links); }
void BM_RandomRaysInLinkSizedBatches(benchmark::State& state) { batches(state, cornell().random); }

void every_query(benchmark::internal::Benchmark* b) {
  for (ShadowQuery q : {ShadowQuery::kSingle, ShadowQuery::kStream, ShadowQuery::kPacket4, ShadowQuery::kPacket8,
                        ShadowQuery::kPacket16}) {
    b->Arg(static_cast<int>(q));
  }
  b->Unit(benchmark::kMillisecond);
}

BENCHMARK(BM_RandomRaysOneBatch)->Apply(every_query);
BENCHMARK(BM_RandomRaysInLinkSizedBatches)->Apply(every_query);
BENCHMARK(BM_LinkBatches)->Apply(every_query);

}  // namespace
}  // namespace lhr

BENCHMARK_MAIN();
