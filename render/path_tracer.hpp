#pragma once
// The reference image (docs/design.md §5 "Reference"): unbiased Monte Carlo path
// tracing of the Lambertian scenes of the scene contract (§3), with
// next-event estimation on emitters (triangles picked in proportion to their
// power, points uniform by area), cosine-weighted bounces, the two combined
// by multiple importance sampling, and Russian roulette. It builds its own
// Embree scene from the input polygons (render/polygon_triangulation) and
// shares no transport code with the radiosity solvers: no form factor,
// visibility, link or solver code, and no tone map. So it is an independent
// check of them, aligned pixel for pixel with the Gouraud view. What it does
// take from radiosity/, none of which computes light: the Rec. 709 luminance
// weights (radiosity/tone_map.hpp), in which its noise is measured; the hash
// its random numbers come from (radiosity/sampling.hpp); and the probe
// directions that tell a point inside a closed object (radiosity/sampling.hpp),
// so that a vertex on a contact line takes its value from the same side in
// both. With the solvers' images it shares the camera model (mesh/scene.hpp,
// render/camera_rays).

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <vector>

#include "mesh/image.hpp"
#include "mesh/scene.hpp"

namespace lhr {

struct PathTraceOptions {
  int spp = 64;  // samples per pixel (of the first round when a target noise is set)
  std::uint64_t seed = 1;
  // > 0: keep doubling the samples in rounds until the relative noise is at
  // most this or max_spp is reached. The result equals one render at the
  // final sample count: sample i of a pixel is the same in either.
  double target_noise = 0.0;
  int max_spp = 1024;
  // false: every sample through the pixel centre, the point the Gouraud view
  // samples (docs/design.md §5), so the metrics compare values at the same points and
  // edges are not penalised for aliasing; true: samples uniform over each
  // pixel (box filter), an antialiased image.
  bool jitter = false;
  // Called before each pixel of each round, from worker threads; may throw
  // to abandon the render (an interrupted run), which render() rethrows.
  std::function<void()> checkpoint;
};

struct PathTraceProgress {
  int spp_done = 0;        // samples per pixel finished before this round
  int spp_round_end = 0;   // samples per pixel when this round ends
  double round_fraction = 0.0;
  double noise = 0.0;  // relative noise of the spp_done samples (0 in the first round)
};

struct ReferenceImage {
  Image radiance;  // mean radiance per pixel, scene units; 0 where nothing is seen
  // 1 where the ray through the pixel centre hits a surface (as in the
  // Gouraud view); metrics exclude the other pixels as background.
  std::vector<std::uint8_t> mask;
  // Per pixel: standard error of the mean luminance, from the sample variance.
  std::vector<float> standard_error;
  int spp = 0;
  int rounds = 0;
  // Noise from two half-sample images A (even samples) and B (odd samples):
  // the mean of all samples has standard error |A−B|/2 per pixel (for equal
  // halves), so noise_rms is the RMS of that over the masked pixels
  // (luminance, scene units) and noise = noise_rms / mean_luminance.
  double noise = 0.0;
  double noise_rms = 0.0;
  double mean_luminance = 0.0;  // over the masked pixels
};

// Where paths for the radiance leaving a given surface point start (the
// per-vertex reference, docs/design.md §5 "How accuracy is judged").
struct SurfaceStart {
  int triangle = -1;  // the scene triangle the point lies on: its Kd, Ke and normal apply
  Vec3 point;         // on that triangle
  Vec3 origin;        // where rays leave: off the plane, toward the surface's inside
};

class PathTracer {
 public:
  // Triangulates every input polygon of every surface (fan, or ear clipping
  // for non-convex ones). Throws std::runtime_error naming a surface whose
  // polygon cannot be triangulated.
  explicit PathTracer(const Scene& scene);
  ~PathTracer();
  PathTracer(const PathTracer&) = delete;
  PathTracer& operator=(const PathTracer&) = delete;

  // Results depend on (scene, camera, options) only, not on the thread count.
  // progress is called from worker threads, one call at a time.
  ReferenceImage render(const Camera& camera, const PathTraceOptions& options,
                        const std::function<void(const PathTraceProgress&)>& progress = {}) const;

  // 1 where the ray through the pixel centre hits a surface.
  std::vector<std::uint8_t> coverage(const Camera& camera) const;
  // Per pixel: the index in Scene::surfaces of the surface the ray through
  // the pixel centre hits first, or -1 (per-surface comparisons).
  std::vector<std::int32_t> pixel_surfaces(const Camera& camera) const;

  // The scene triangle under x whose front faces along `normal`, with x
  // moved slightly toward `toward` (a point inside the same surface, e.g. a
  // mesh face's centroid): on a crease or in a corner x lies on several
  // surfaces, and its value is the limit from inside its own, so its paths
  // must not start on or behind the neighbour. A point off every triangle
  // (a vertex refined across a fold of a curved surface) moves to the
  // nearest front-facing one. nullopt when none is within 1e-3 of the scene
  // size.
  std::optional<SurfaceStart> surface_start(const Vec3& x, const Vec3& normal, const Vec3& toward) const;

  // The fraction of a fixed set of directions over start's front hemisphere
  // whose first hit is the back of a triangle: about 1 when start lies
  // inside a closed object (a floor point under a box standing on it), 0 in
  // the open. Deterministic.
  double enclosed_fraction(const SurfaceStart& start) const;

  // One unbiased sample of the radiance leaving start.point toward its
  // front, Le + Kd/π·E, with the machinery of render(); the random numbers
  // are a function of key alone.
  Rgb sample_radiance(const SurfaceStart& start, std::uint64_t key) const;

  // The unit front normal of a scene triangle (a SurfaceStart's).
  Vec3 triangle_normal(int triangle) const;

  std::size_t triangle_count() const;
  std::size_t emitter_triangle_count() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace lhr
