#include "render/path_tracer.hpp"

#include <embree3/rtcore.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <string>

#include "mesh/triangle_geometry.hpp"
#include "radiosity/sampling.hpp"
#include "radiosity/tone_map.hpp"
#include "render/camera_rays.hpp"
#include "render/polygon_triangulation.hpp"

namespace lhr {

namespace {

// Embree stores float coordinates: a hit is exact to about 1e-7 of the
// coordinates' magnitude, so ray origins are lifted off their surface by more.
constexpr double kRelativeEpsilon = 1e-5;
// Russian roulette keeps a path with probability min(this, max throughput):
// below 1 so that paths end even where Kd is close to 1.
constexpr double kMaxSurvival = 0.95;
// A guard, not a truncation that matters: surviving this many bounces has
// probability below 0.95^1000 ≈ 5e-23.
constexpr int kMaxBounces = 1000;
// A scene triangle counts as the surface a mesh vertex lies on only if its
// front is within 60° of the vertex's normal: a mesh refines its input
// polygons, so the two agree but for rounding, while a surface met at a
// crease or the back of a thin wall faces elsewhere.
constexpr double kFacingCosine = 0.5;
// How far (in ray offsets, 1e-5 of the scene size) the short ray looks for
// a vertex's surface: float storage of mesh coordinates is far closer.
constexpr double kLocateReach = 4.0;
// How far the nearest-triangle fallback looks: a curved surface is meshed as
// facets whose refined vertices (midpoints of edges across a fold) lie off
// the input polygons by the fold's sag: about 1e-4 of the scene size on the
// Cornell box's left wall (3.2 mm out of true over 560 mm), 1e-3 on a UV
// sphere of 32 × 16 segments filling a fifth of its room. A mesh of another
// scene lies much further off.
constexpr double kFallbackReach = 1000.0;

// Counter-based stream: each draw hashes (key, counter), so a sample's
// numbers depend only on (seed, pixel, sample index), never on thread order.
class SampleStream {
 public:
  explicit SampleStream(std::uint64_t key) : state_(key) {}
  double next() {
    state_ += 0x9E3779B97F4A7C15ull;
    return unit_double(state_);
  }

 private:
  std::uint64_t state_;
};

// An orthonormal frame around unit n (Duff et al. 2017, branchless).
void frame_around(const Vec3& n, Vec3& t, Vec3& b) {
  const double sign = std::copysign(1.0, n[2]);
  const double a = -1.0 / (sign + n[2]);
  const double c = n[0] * n[1] * a;
  t = Vec3(1.0 + sign * n[0] * n[0] * a, sign * c, -sign * n[0]);
  b = Vec3(c, sign + n[1] * n[1] * a, -n[1]);
}

void throw_on_error(RTCDevice device, const char* what) {
  const RTCError error = rtcGetDeviceError(device);
  if (error != RTC_ERROR_NONE) {
    throw std::runtime_error(std::string("Embree failed while ") + what + " (error " +
                             std::to_string(static_cast<int>(error)) + ")");
  }
}

struct Triangle {
  std::array<Vec3, 3> corners;
  Vec3 normal;  // unit, front side
  Vec3 centroid;
  double area = 0.0;
  int material = 0;
  int surface = 0;  // index into Scene::surfaces
  double pick_probability = 0.0;  // of next-event estimation choosing it; 0 unless it emits
};

// Per-pixel sums over the samples so far, in sample order.
struct PixelSums {
  double half[2][3] = {{0, 0, 0}, {0, 0, 0}};  // even and odd samples
  double mean_luminance = 0.0;                 // Welford's running mean and
  double m2_luminance = 0.0;                   // sum of squared deviations
};

}  // namespace

struct PathTracer::Impl {
  std::vector<Triangle> triangles;
  std::vector<Material> materials;
  std::vector<int> emitters;            // triangle indices
  std::vector<double> emitter_cdf;      // cumulative pick probabilities, last = 1
  double epsilon = 0.0;
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;

  struct Hit {
    int triangle;
    double distance;
    double u, v;  // barycentrics of corners 1 and 2
  };

  std::optional<Hit> intersect(const Vec3& origin, const Vec3& direction, float t_near = 0.0f,
                               float t_far = std::numeric_limits<float>::infinity()) const {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRayHit rayhit{};
    rayhit.ray.org_x = static_cast<float>(origin[0]);
    rayhit.ray.org_y = static_cast<float>(origin[1]);
    rayhit.ray.org_z = static_cast<float>(origin[2]);
    rayhit.ray.dir_x = static_cast<float>(direction[0]);
    rayhit.ray.dir_y = static_cast<float>(direction[1]);
    rayhit.ray.dir_z = static_cast<float>(direction[2]);
    rayhit.ray.tnear = t_near;
    rayhit.ray.tfar = t_far;
    rayhit.ray.mask = 0xFFFFFFFFu;
    rayhit.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(scene, &context, &rayhit);
    if (rayhit.hit.geomID == RTC_INVALID_GEOMETRY_ID) return std::nullopt;
    return Hit{static_cast<int>(rayhit.hit.primID), static_cast<double>(rayhit.ray.tfar),
               static_cast<double>(rayhit.hit.u), static_cast<double>(rayhit.hit.v)};
  }

  bool occluded(const Vec3& from, const Vec3& to) const {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRay ray{};
    const Vec3 d = to - from;
    ray.org_x = static_cast<float>(from[0]);
    ray.org_y = static_cast<float>(from[1]);
    ray.org_z = static_cast<float>(from[2]);
    ray.dir_x = static_cast<float>(d[0]);
    ray.dir_y = static_cast<float>(d[1]);
    ray.dir_z = static_cast<float>(d[2]);
    ray.tnear = 0.0f;
    ray.tfar = 1.0f;
    ray.mask = 0xFFFFFFFFu;
    rtcOccluded1(scene, &context, &ray);
    return ray.tfar < 0.0f;
  }

  // The hit point from its barycentrics, so it lies on its triangle, never
  // beyond an edge: a point found as origin + t·direction can land just
  // outside a closed room where two walls meet, and its next ray escape.
  Vec3 surface_point(const Hit& hit) const {
    const auto& c = triangles[hit.triangle].corners;
    return (1.0 - hit.u - hit.v) * c[0] + hit.u * c[1] + hit.v * c[2];
  }

  // Where rays leave a point x of triangle t: lifted off the plane and drawn
  // toward the triangle's inside, so that near a concave edge the origin is
  // strictly inside the room rather than on the neighbouring wall's plane.
  Vec3 ray_origin(const Vec3& x, const Triangle& t) const {
    Vec3 inward = t.centroid - x;
    const double length = inward.norm();
    if (length > 0) inward /= length;
    return x + epsilon * (t.normal + inward);
  }

  // First along a short ray down the normal through the nudged point (the
  // triangle right under it, found by Embree in float like every other
  // hit); failing that, the nearest front-facing triangle by brute force.
  std::optional<SurfaceStart> surface_start(const Vec3& x, const Vec3& normal, const Vec3& toward) const {
    const double normal_length = normal.norm();
    if (!(normal_length > 0)) return std::nullopt;
    const Vec3 n = normal / normal_length;
    Vec3 inward = toward - x;
    inward -= OpenMesh::dot(inward, n) * n;
    const double inward_length = inward.norm();
    // Never past the target point, so the nudge stays inside the face.
    const double nudge = std::min(epsilon, 0.5 * inward_length);
    if (inward_length > 0) inward /= inward_length;
    const Vec3 p = x + nudge * inward;
    const auto start_on = [&](int index, const Vec3& point) {
      const Triangle& t = triangles[index];
      return SurfaceStart{index, point, point + epsilon * (t.normal + inward)};
    };
    const Vec3 above = p + (0.5 * kLocateReach * epsilon) * n;
    float t_near = 0.0f;
    for (int attempt = 0; attempt < 8; ++attempt) {
      const auto hit = intersect(above, -n, t_near, static_cast<float>(kLocateReach * epsilon));
      if (!hit) break;
      if (OpenMesh::dot(triangles[hit->triangle].normal, n) > kFacingCosine) {
        return start_on(hit->triangle, surface_point(*hit));
      }
      t_near = std::nextafter(static_cast<float>(hit->distance), std::numeric_limits<float>::infinity());
    }
    int best = -1;
    Vec3 best_point;
    double best_distance = kFallbackReach * epsilon;
    for (std::size_t i = 0; i < triangles.size(); ++i) {
      const Triangle& t = triangles[i];
      if (!(OpenMesh::dot(t.normal, n) > kFacingCosine)) continue;
      const Vec3 q = closest_point(p, t.corners);
      const double d = (q - p).norm();
      if (d <= best_distance) {
        best = static_cast<int>(i);
        best_point = q;
        best_distance = d;
      }
    }
    if (best < 0) return std::nullopt;
    return start_on(best, best_point);
  }

  // Probability density, per unit solid angle at x, that next-event
  // estimation picks the point y on emitter triangle `index` at squared
  // distance d2, seen under cosθy at y.
  double emitter_density(int index, double d2, double cos_y) const {
    return triangles[index].pick_probability / triangles[index].area * d2 / cos_y;
  }

  // Next-event estimation at x (unit normal n): a point sampled on the
  // emitters by area, weighted by the balance heuristic against the cosine
  // bounce (Veach and Guibas 1995). Returns an estimate of the weighted part
  // of ∫ Ke cosθx V / π dω, to be multiplied by Kd. The weight bounds the
  // estimate by Ke, where plain area sampling has unbounded variance (x near
  // an emitter that meets its surface at a corner, as in the furnace).
  Rgb direct(const Vec3& x, const Vec3& origin, const Vec3& n, SampleStream& rng) const {
    const double pick = rng.next();
    const double s = rng.next(), t = rng.next();
    if (emitters.empty()) return Rgb(0, 0, 0);
    const std::size_t k = std::min<std::size_t>(
        static_cast<std::size_t>(std::upper_bound(emitter_cdf.begin(), emitter_cdf.end(), pick) - emitter_cdf.begin()),
        emitters.size() - 1);
    const Triangle& e = triangles[emitters[k]];
    // Uniform point on the triangle (square-root parametrisation).
    const double r = std::sqrt(s);
    const Vec3 y = (1.0 - r) * e.corners[0] + r * (1.0 - t) * e.corners[1] + r * t * e.corners[2];
    Vec3 w = y - x;
    const double d2 = w.sqrnorm();
    if (!(d2 > 0)) return Rgb(0, 0, 0);
    w /= std::sqrt(d2);
    const double cos_x = OpenMesh::dot(n, w);
    const double cos_y = -OpenMesh::dot(e.normal, w);
    if (cos_x <= 0 || cos_y <= 0) return Rgb(0, 0, 0);
    if (occluded(origin, ray_origin(y, e))) return Rgb(0, 0, 0);
    // (Ke cosθx/π) / p_light, times p_light / (p_light + p_bounce).
    const double p_bounce = cos_x / M_PI;
    return materials[e.material].emission * (p_bounce / (emitter_density(emitters[k], d2, cos_y) + p_bounce));
  }

  // One path from the camera: Ke where the camera ray lands in full; at
  // every later vertex next-event estimation, and Ke where a bounce lands on
  // an emitter, each with its balance-heuristic weight. `hit` is where the
  // camera ray in `direction` lands, traced by the caller (once per pixel
  // when every sample goes through the pixel centre).
  Rgb radiance(const Vec3& direction, std::optional<Hit> hit, SampleStream& rng) const {
    if (!hit) return Rgb(0, 0, 0);
    const Triangle& tri = triangles[hit->triangle];
    if (OpenMesh::dot(tri.normal, direction) >= 0) return Rgb(0, 0, 0);  // back sides are black (docs/design.md §3)
    const Vec3 x = surface_point(*hit);
    return radiance_leaving(hit->triangle, x, ray_origin(x, tri), rng);
  }

  // The radiance leaving x on triangle `index` toward its front, its rays
  // leaving from `first_origin` at the first vertex of the path.
  Rgb radiance_leaving(int index, Vec3 x, const Vec3& first_origin, SampleStream& rng) const {
    const Triangle* tri = &triangles[index];
    Rgb sum = materials[tri->material].emission;
    Rgb throughput(1, 1, 1);
    for (int bounce = 0; bounce < kMaxBounces; ++bounce) {
      const Rgb& kd = materials[tri->material].reflectance;
      if (!(max_channel(kd) > 0)) break;
      const Vec3& n = tri->normal;
      const Vec3 origin = bounce == 0 ? first_origin : ray_origin(x, *tri);
      sum += throughput * (kd * direct(x, origin, n, rng));
      // Cosine-weighted sampling: BRDF·cos/pdf = Kd.
      throughput = throughput * kd;
      const double survive = std::min(kMaxSurvival, max_channel(throughput));
      if (!(rng.next() < survive)) break;
      throughput /= survive;
      const double u = rng.next(), v = rng.next();
      Vec3 t, b;
      frame_around(n, t, b);
      const double r = std::sqrt(u), phi = 2.0 * M_PI * v;
      const double cos_x = std::sqrt(std::max(0.0, 1.0 - u));
      const Vec3 dir = (r * std::cos(phi)) * t + (r * std::sin(phi)) * b + cos_x * n;
      const auto hit = intersect(origin, dir);
      if (!hit) break;
      tri = &triangles[hit->triangle];
      const double cos_y = -OpenMesh::dot(tri->normal, dir);
      if (!(cos_y > 0)) break;
      x = surface_point(*hit);
      if (tri->pick_probability > 0) {
        const double p_bounce = cos_x / M_PI;
        const double d2 = hit->distance * hit->distance;
        const double weight = p_bounce / (p_bounce + emitter_density(hit->triangle, d2, cos_y));
        sum += throughput * materials[tri->material].emission * weight;
      }
    }
    return sum;
  }
};

PathTracer::PathTracer(const Scene& scene) : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  m.materials = scene.materials;
  double magnitude = 0.0;
  const Bounds bounds = scene_bounds(scene);
  for (std::size_t si = 0; si < scene.surfaces.size(); ++si) {
    const Surface& surface = scene.surfaces[si];
    if (surface.material < 0 || surface.material >= static_cast<int>(m.materials.size())) {
      throw std::runtime_error("surface " + surface.name + ": material index out of range");
    }
    for (const Vec3& p : surface.points) {
      magnitude = std::max({magnitude, std::abs(p[0]), std::abs(p[1]), std::abs(p[2])});
    }
    for (std::size_t pi = 0; pi < surface.polygons.size(); ++pi) {
      const std::vector<int>& poly = surface.polygons[pi];
      // Newell's normal: the polygon's front even when it is not convex.
      Vec3 normal(0, 0, 0);
      for (std::size_t i = 0; i < poly.size(); ++i) {
        normal += OpenMesh::cross(surface.points[poly[i]], surface.points[poly[(i + 1) % poly.size()]]);
      }
      if (!(normal.norm() > 0)) continue;  // zero area: nothing to hit
      normal.normalize();
      Vec3 u, v;
      frame_around(normal, u, v);
      std::vector<std::array<double, 2>> q;
      for (int i : poly) q.push_back({OpenMesh::dot(surface.points[i], u), OpenMesh::dot(surface.points[i], v)});
      const auto pieces = triangulate_planar_polygon(q);
      if (!pieces) {
        throw std::runtime_error("surface " + surface.name + ": polygon " + std::to_string(pi) +
                                 " is self-intersecting; the path tracer cannot triangulate it");
      }
      for (const auto& piece : *pieces) {
        Triangle t;
        for (int k = 0; k < 3; ++k) t.corners[k] = surface.points[poly[piece[k]]];
        const Vec3 c = OpenMesh::cross(t.corners[1] - t.corners[0], t.corners[2] - t.corners[0]);
        t.area = 0.5 * c.norm();
        if (!(t.area > 0)) continue;
        t.normal = c / (2.0 * t.area);
        t.centroid = (t.corners[0] + t.corners[1] + t.corners[2]) / 3.0;
        t.material = surface.material;
        t.surface = static_cast<int>(si);
        m.triangles.push_back(t);
      }
    }
  }
  m.epsilon = kRelativeEpsilon * std::max({bounds.diagonal(), magnitude, 1e-30});

  // Emitters are picked in proportion to their power (area × summed Ke).
  double total = 0.0;
  std::vector<double> weights;
  for (std::size_t i = 0; i < m.triangles.size(); ++i) {
    const Material& mat = m.materials[m.triangles[i].material];
    if (!mat.is_emitter()) continue;
    const double w = m.triangles[i].area * (mat.emission[0] + mat.emission[1] + mat.emission[2]);
    if (!(w > 0)) continue;
    m.emitters.push_back(static_cast<int>(i));
    weights.push_back(w);
    total += w;
  }
  double running = 0.0;
  for (std::size_t k = 0; k < weights.size(); ++k) {
    running += weights[k];
    m.emitter_cdf.push_back(running / total);
    m.triangles[m.emitters[k]].pick_probability = weights[k] / total;
  }
  if (!m.emitter_cdf.empty()) m.emitter_cdf.back() = 1.0;

  m.device = rtcNewDevice("threads=0");
  if (!m.device) throw std::runtime_error("cannot create an Embree device");
  m.scene = rtcNewScene(m.device);
  // Robust mode: rays grazing shared edges must not leak through.
  rtcSetSceneFlags(m.scene, RTC_SCENE_FLAG_ROBUST);
  rtcSetSceneBuildQuality(m.scene, RTC_BUILD_QUALITY_HIGH);
  if (!m.triangles.empty()) {
    RTCGeometry geometry = rtcNewGeometry(m.device, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                                 3 * sizeof(float), 3 * m.triangles.size()));
    auto* indices = static_cast<unsigned*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                                   3 * sizeof(unsigned), m.triangles.size()));
    throw_on_error(m.device, "allocating geometry");
    for (std::size_t i = 0; i < m.triangles.size(); ++i) {
      for (int k = 0; k < 3; ++k) {
        for (int c = 0; c < 3; ++c) vertices[9 * i + 3 * k + c] = static_cast<float>(m.triangles[i].corners[k][c]);
        indices[3 * i + k] = static_cast<unsigned>(3 * i + k);
      }
    }
    rtcCommitGeometry(geometry);
    rtcAttachGeometry(m.scene, geometry);
    rtcReleaseGeometry(geometry);
  }
  rtcCommitScene(m.scene);
  throw_on_error(m.device, "building the scene");
}

PathTracer::~PathTracer() {
  if (impl_->scene) rtcReleaseScene(impl_->scene);
  if (impl_->device) rtcReleaseDevice(impl_->device);
}

std::optional<SurfaceStart> PathTracer::surface_start(const Vec3& x, const Vec3& normal, const Vec3& toward) const {
  return impl_->surface_start(x, normal, toward);
}

double PathTracer::enclosed_fraction(const SurfaceStart& start) const {
  if (start.triangle < 0 || start.triangle >= static_cast<int>(impl_->triangles.size())) {
    throw std::invalid_argument("path tracer: a surface start names no triangle of the scene");
  }
  const std::vector<Vec3> directions = hemisphere_probe_directions(impl_->triangles[start.triangle].normal);
  int back = 0;
  for (const Vec3& d : directions) {
    const auto hit = impl_->intersect(start.origin, d);
    if (hit && OpenMesh::dot(impl_->triangles[hit->triangle].normal, d) > 0.0) ++back;
  }
  return static_cast<double>(back) / static_cast<double>(directions.size());
}

Rgb PathTracer::sample_radiance(const SurfaceStart& start, std::uint64_t key) const {
  if (start.triangle < 0 || start.triangle >= static_cast<int>(impl_->triangles.size())) {
    throw std::invalid_argument("path tracer: a surface start names no triangle of the scene");
  }
  SampleStream rng(key);
  return impl_->radiance_leaving(start.triangle, start.point, start.origin, rng);
}

Vec3 PathTracer::triangle_normal(int triangle) const {
  if (triangle < 0 || triangle >= static_cast<int>(impl_->triangles.size())) {
    throw std::invalid_argument("path tracer: no triangle " + std::to_string(triangle) + " in the scene");
  }
  return impl_->triangles[triangle].normal;
}

std::size_t PathTracer::triangle_count() const { return impl_->triangles.size(); }
std::size_t PathTracer::emitter_triangle_count() const { return impl_->emitters.size(); }

std::vector<std::uint8_t> PathTracer::coverage(const Camera& camera) const {
  const CameraRays rays(camera);
  std::vector<std::uint8_t> mask(static_cast<std::size_t>(camera.width) * camera.height, 0);
  tbb::parallel_for(0, camera.height, [&](int y) {
    for (int x = 0; x < camera.width; ++x) {
      const bool hit = impl_->intersect(rays.origin(), rays.direction(x, y)).has_value();
      mask[static_cast<std::size_t>(y) * camera.width + x] = hit ? 1 : 0;
    }
  });
  return mask;
}

std::vector<std::int32_t> PathTracer::pixel_surfaces(const Camera& camera) const {
  const CameraRays rays(camera);
  std::vector<std::int32_t> surfaces(static_cast<std::size_t>(camera.width) * camera.height, -1);
  tbb::parallel_for(0, camera.height, [&](int y) {
    for (int x = 0; x < camera.width; ++x) {
      const auto hit = impl_->intersect(rays.origin(), rays.direction(x, y));
      if (hit) surfaces[static_cast<std::size_t>(y) * camera.width + x] = impl_->triangles[hit->triangle].surface;
    }
  });
  return surfaces;
}

ReferenceImage PathTracer::render(const Camera& camera, const PathTraceOptions& options,
                                  const std::function<void(const PathTraceProgress&)>& progress) const {
  if (camera.width <= 0 || camera.height <= 0) throw std::invalid_argument("path tracer: the camera has no pixels");
  if (options.spp < 2) {
    throw std::invalid_argument("path tracer: at least 2 samples per pixel (the noise needs two halves)");
  }
  if (options.target_noise > 0 && options.max_spp < options.spp) {
    throw std::invalid_argument("path tracer: the maximum samples per pixel is below the first round's");
  }
  const Impl& m = *impl_;
  const CameraRays rays(camera);
  const int width = camera.width, height = camera.height;
  const std::size_t pixel_count = static_cast<std::size_t>(width) * height;
  std::vector<PixelSums> sums(pixel_count);

  ReferenceImage result;
  result.mask = coverage(camera);
  int done = 0;
  int round_spp = options.spp;
  std::mutex progress_mutex;
  while (true) {
    const int first = done, last = done + round_spp;
    std::atomic<int> rows_done{0};
    tbb::parallel_for(tbb::blocked_range<int>(0, height), [&](const tbb::blocked_range<int>& range) {
      for (int y = range.begin(); y != range.end(); ++y) {
        for (int x = 0; x < width; ++x) {
          if (options.checkpoint) options.checkpoint();
          const std::size_t pixel = static_cast<std::size_t>(y) * width + x;
          PixelSums& p = sums[pixel];
          const Vec3 centre = rays.direction(x, y);
          const auto centre_hit = options.jitter ? std::nullopt : m.intersect(rays.origin(), centre);
          for (int s = first; s < last; ++s) {
            SampleStream rng(sample_key(options.seed, pixel, static_cast<std::uint64_t>(s)));
            Rgb l;
            if (options.jitter) {
              const double jx = rng.next(), jy = rng.next();
              const Vec3 d = rays.direction_at(x + jx, y + jy);
              l = m.radiance(d, m.intersect(rays.origin(), d), rng);
            } else {
              l = m.radiance(centre, centre_hit, rng);
            }
            for (int c = 0; c < 3; ++c) p.half[s & 1][c] += l[c];
            const double lum = luminance(l);
            const double delta = lum - p.mean_luminance;
            p.mean_luminance += delta / (s + 1);
            p.m2_luminance += delta * (lum - p.mean_luminance);
          }
        }
        const int finished = ++rows_done;
        if (progress) {
          const std::lock_guard<std::mutex> lock(progress_mutex);
          progress({first, last, static_cast<double>(finished) / height, result.noise});
        }
      }
    });
    done = last;
    ++result.rounds;

    // Noise from the two halves; serial, so the sums do not depend on threads.
    const double n_even = (done + 1) / 2, n_odd = done / 2;
    const double half_factor = n_even * n_odd / (static_cast<double>(done) * done);
    double se2_sum = 0.0, luminance_sum = 0.0;
    std::size_t covered = 0;
    for (std::size_t i = 0; i < pixel_count; ++i) {
      if (!result.mask[i]) continue;
      Rgb a, b, mean;
      for (int c = 0; c < 3; ++c) {
        a[c] = sums[i].half[0][c] / n_even;
        b[c] = sums[i].half[1][c] / n_odd;
        mean[c] = (sums[i].half[0][c] + sums[i].half[1][c]) / done;
      }
      const double d = luminance(a) - luminance(b);
      se2_sum += d * d * half_factor;
      luminance_sum += luminance(mean);
      ++covered;
    }
    result.spp = done;
    result.noise_rms = covered ? std::sqrt(se2_sum / covered) : 0.0;
    result.mean_luminance = covered ? luminance_sum / covered : 0.0;
    result.noise = result.mean_luminance > 0 ? result.noise_rms / result.mean_luminance : 0.0;
    if (!(options.target_noise > 0) || result.noise <= options.target_noise || done >= options.max_spp) break;
    round_spp = std::min(done, options.max_spp - done);
  }

  result.radiance = Image(width, height);
  result.standard_error.assign(pixel_count, 0.0f);
  for (std::size_t i = 0; i < pixel_count; ++i) {
    for (int c = 0; c < 3; ++c) {
      result.radiance.rgb[3 * i + c] = static_cast<float>((sums[i].half[0][c] + sums[i].half[1][c]) / result.spp);
    }
    const double variance = sums[i].m2_luminance / (result.spp - 1);
    result.standard_error[i] = static_cast<float>(std::sqrt(std::max(0.0, variance) / result.spp));
  }
  return result;
}

}  // namespace lhr
