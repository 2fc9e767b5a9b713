#include "render/vertex_reference.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <string>

#include "radiosity/sampling.hpp"
#include "radiosity/tone_map.hpp"
#include "render/image_metrics.hpp"

namespace lhr {

namespace {

// Per vertex: the summed area normal of its faces and the centroids of its
// faces, widest corner first. Nudging toward a centroid moves into a face
// for certain, where an average direction over a boundary vertex's fan
// could leave the surface.
struct VertexFrame {
  Vec3 normal = Vec3(0, 0, 0);
  std::vector<std::pair<double, Vec3>> faces;  // (corner angle, centroid)
  double widest = -1.0;
};

std::vector<VertexFrame> vertex_frames(const RawMesh& mesh) {
  const std::size_t n = mesh.points.size();
  std::vector<VertexFrame> frames(n);
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    const std::vector<int>& face = mesh.faces[f];
    if (face.size() != 3) {
      throw std::invalid_argument("face " + std::to_string(f) + " has " + std::to_string(face.size()) +
                                  " vertices; expected the triangles lhr solve exports");
    }
    for (int v : face) {
      if (v < 0 || static_cast<std::size_t>(v) >= n) {
        throw std::invalid_argument("face " + std::to_string(f) + " has vertex index " + std::to_string(v) +
                                    ", not in [0, " + std::to_string(n) + ")");
      }
    }
    if (face[0] == face[1] || face[1] == face[2] || face[2] == face[0]) {
      throw std::invalid_argument("face " + std::to_string(f) + " repeats a vertex");
    }
    const Vec3& a = mesh.points[face[0]];
    const Vec3& b = mesh.points[face[1]];
    const Vec3& c = mesh.points[face[2]];
    const Vec3 area_normal = OpenMesh::cross(b - a, c - a);
    const Vec3 centroid = (a + b + c) / 3.0;
    for (int k = 0; k < 3; ++k) {
      const Vec3& p = mesh.points[face[k]];
      const Vec3 e1 = mesh.points[face[(k + 1) % 3]] - p;
      const Vec3 e2 = mesh.points[face[(k + 2) % 3]] - p;
      const double angle = std::atan2(OpenMesh::cross(e1, e2).norm(), OpenMesh::dot(e1, e2));
      VertexFrame& frame = frames[face[k]];
      frame.normal += area_normal;
      frame.faces.emplace_back(angle, centroid);
      frame.widest = std::max(frame.widest, angle);
    }
  }
  for (std::size_t v = 0; v < n; ++v) {
    std::stable_sort(frames[v].faces.begin(), frames[v].faces.end(),
                     [](const auto& a, const auto& b) { return a.first > b.first; });
    if (frames[v].widest < 0) {
      throw std::invalid_argument("vertex " + std::to_string(v) + " at " + describe_point(mesh.points[v]) +
                                  " belongs to no face, so the side it faces is unknown");
    }
    if (!(frames[v].normal.norm() > 0)) {
      throw std::invalid_argument("vertex " + std::to_string(v) + " at " + describe_point(mesh.points[v]) +
                                  " has only zero-area faces, so the side it faces is unknown");
    }
  }
  return frames;
}

// Where a vertex's paths start, and with what share of its samples.
//
// A vertex on a contact line (a floor vertex at the foot of a box, a ceiling
// vertex on the outline of a light just below it) has faces on both sides,
// and the radiance jumps there: its value is the limit from the side that
// can be seen, the face whose start is least enclosed (widest first among
// equals). A vertex where a curved surface bends (docs/accuracy.md, "Facet
// edges") has open faces in more than one input plane, and the radiance
// jumps there too; its value is, as the scene contract defines a node's
// there (docs/design.md §3), the mean of the one-sided limits, each plane
// weighted by the corner angles its faces make at the vertex. So: per plane
// the least enclosed start, and every plane whose start is not clearly more
// enclosed than the best one shares the samples by its angle.
struct VertexStarts {
  std::vector<SurfaceStart> starts;
  std::vector<double> cumulative;  // shares, summing to 1
};

std::optional<VertexStarts> vertex_starts(const PathTracer& tracer, const Vec3& x, const VertexFrame& frame) {
  constexpr double kClearlyMoreOpen = 0.125;
  constexpr double kSamePlane = 1.0 - 1e-9;
  struct Plane {
    Vec3 normal;
    SurfaceStart start;
    double enclosed;
    double angle;
  };
  std::vector<Plane> planes;
  for (const auto& [angle, centroid] : frame.faces) {
    std::optional<SurfaceStart> start = tracer.surface_start(x, frame.normal, centroid);
    if (!start) continue;
    const Vec3 normal = tracer.triangle_normal(start->triangle);
    auto plane = std::find_if(planes.begin(), planes.end(),
                              [&](const Plane& p) { return OpenMesh::dot(p.normal, normal) > kSamePlane; });
    if (plane == planes.end()) {
      planes.push_back({normal, *start, tracer.enclosed_fraction(*start), angle});
      continue;
    }
    plane->angle += angle;
    if (plane->enclosed == 0.0) continue;
    const double enclosed = tracer.enclosed_fraction(*start);
    if (enclosed < plane->enclosed - kClearlyMoreOpen) {
      plane->start = *start;
      plane->enclosed = enclosed;
    }
  }
  if (planes.empty()) return std::nullopt;
  double best = planes.front().enclosed;
  for (const Plane& p : planes) best = std::min(best, p.enclosed);
  VertexStarts out;
  double total = 0.0;
  for (const Plane& p : planes) {
    if (p.enclosed > best + kClearlyMoreOpen) continue;
    out.starts.push_back(p.start);
    total += p.angle;
    out.cumulative.push_back(total);
  }
  for (double& c : out.cumulative) c /= total;
  return out;
}

// Which start sample k of a vertex leaves from: a golden-ratio sequence over
// the shares, so each start gets its share of any number of samples to
// within one, the same whatever the thread count.
const SurfaceStart& start_of_sample(const VertexStarts& v, int k) {
  if (v.starts.size() == 1) return v.starts.front();
  constexpr double kGolden = 0.6180339887498949;
  const double u = std::fmod(0.5 + kGolden * static_cast<double>(k), 1.0);
  const std::size_t i = static_cast<std::size_t>(std::lower_bound(v.cumulative.begin(), v.cumulative.end(), u) -
                                                 v.cumulative.begin());
  return v.starts[std::min(i, v.starts.size() - 1)];
}

// Per-vertex sums over the samples so far, in sample order.
struct VertexSums {
  Rgb sum = Rgb(0, 0, 0);
  double mean_luminance = 0.0;  // Welford's running mean and
  double m2_luminance = 0.0;    // sum of squared deviations
};

}  // namespace

VertexReference trace_vertex_reference(const PathTracer& tracer, const RawMesh& mesh, const PathTraceOptions& options,
                                       const std::function<void(const PathTraceProgress&)>& progress) {
  if (options.spp < 2) {
    throw std::invalid_argument("path tracer: at least 2 samples per vertex (the standard error needs two)");
  }
  if (options.target_noise > 0 && options.max_spp < options.spp) {
    throw std::invalid_argument("path tracer: the maximum samples per vertex is below the first round's");
  }
  const std::size_t n = mesh.points.size();
  const std::vector<VertexFrame> frames = vertex_frames(mesh);

  // In chunks, so a mesh of another scene fails after one chunk of the
  // locator's slow fallback rather than all of them, always naming its
  // first vertex that lies on no surface.
  constexpr std::size_t kLocateChunk = 4096;
  std::vector<std::optional<VertexStarts>> starts(n);
  for (std::size_t begin = 0; begin < n; begin += kLocateChunk) {
    const std::size_t end = std::min(n, begin + kLocateChunk);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(begin, end), [&](const tbb::blocked_range<std::size_t>& range) {
      for (std::size_t v = range.begin(); v != range.end(); ++v) {
        starts[v] = vertex_starts(tracer, mesh.points[v], frames[v]);
      }
    });
    for (std::size_t v = begin; v < end; ++v) {
      if (!starts[v]) {
        throw std::invalid_argument("vertex " + std::to_string(v) + " at " + describe_point(mesh.points[v]) +
                                    " lies on no surface of the scene facing its way (is the mesh of this scene?)");
      }
    }
  }

  std::vector<VertexSums> sums(n);
  VertexReference result;
  int done = 0;
  int round_spp = options.spp;
  std::mutex progress_mutex;
  while (true) {
    const int first = done, last = done + round_spp;
    std::atomic<std::size_t> vertices_done{0};
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n), [&](const tbb::blocked_range<std::size_t>& range) {
      for (std::size_t v = range.begin(); v != range.end(); ++v) {
        VertexSums& s = sums[v];
        for (int k = first; k < last; ++k) {
          // Also within a vertex: at many samples per vertex one takes seconds.
          if (options.checkpoint && (k == first || k % 1024 == 0)) options.checkpoint();
          const Rgb l = tracer.sample_radiance(start_of_sample(*starts[v], k),
                                               sample_key(options.seed, v, static_cast<std::uint64_t>(k)));
          s.sum += l;
          const double lum = luminance(l);
          const double delta = lum - s.mean_luminance;
          s.mean_luminance += delta / (k + 1);
          s.m2_luminance += delta * (lum - s.mean_luminance);
        }
      }
      const std::size_t finished = vertices_done += range.size();
      if (progress) {
        const std::lock_guard<std::mutex> lock(progress_mutex);
        progress({first, last, static_cast<double>(finished) / static_cast<double>(n), result.noise});
      }
    });
    done = last;
    ++result.rounds;

    // Serial, so the sums do not depend on the threads.
    double se2_sum = 0.0, luminance_sum = 0.0;
    for (const VertexSums& s : sums) {
      se2_sum += std::max(0.0, s.m2_luminance) / (static_cast<double>(done) - 1) / done;
      luminance_sum += luminance(s.sum / done);
    }
    result.spp = done;
    result.noise_rms = n ? std::sqrt(se2_sum / static_cast<double>(n)) : 0.0;
    result.mean_luminance = n ? luminance_sum / static_cast<double>(n) : 0.0;
    result.noise = result.mean_luminance > 0 ? result.noise_rms / result.mean_luminance : 0.0;
    if (!(options.target_noise > 0) || result.noise <= options.target_noise || done >= options.max_spp) break;
    round_spp = std::min(done, options.max_spp - done);
  }

  result.radiance.reserve(n);
  result.standard_error.reserve(n);
  for (const VertexSums& s : sums) {
    result.radiance.push_back(s.sum / result.spp);
    const double variance = std::max(0.0, s.m2_luminance) / (result.spp - 1);
    result.standard_error.push_back(std::sqrt(variance / result.spp));
  }
  return result;
}

ExportMesh vertex_reference_export(const RawMesh& mesh, const VertexReference& reference, const ToneMapSettings& tone) {
  const std::size_t n = mesh.points.size();
  if (reference.radiance.size() != n || reference.standard_error.size() != n) {
    throw std::invalid_argument("vertex reference: " + std::to_string(reference.radiance.size()) +
                                " values for a mesh of " + std::to_string(n) + " vertices");
  }
  ExportMesh out;
  out.points = mesh.points;
  out.radiance = reference.radiance;
  out.radiance_stderr = reference.standard_error;
  out.triangles.reserve(mesh.faces.size());
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    if (mesh.faces[f].size() != 3) {
      throw std::invalid_argument("face " + std::to_string(f) + " is not a triangle");
    }
    out.triangles.push_back({mesh.faces[f][0], mesh.faces[f][1], mesh.faces[f][2]});
  }
  // The vertices as a one-row image, every pixel seen.
  Image values(static_cast<int>(n), 1);
  for (std::size_t v = 0; v < n; ++v) {
    for (int c = 0; c < 3; ++c) values.rgb[3 * v + c] = static_cast<float>(reference.radiance[v][c]);
  }
  const auto tone_map = reference_tone_map(tone, values, std::vector<std::uint8_t>(n, 1));
  out.colours.reserve(n);
  for (const Rgb& r : reference.radiance) out.colours.push_back(tone_map->display_bytes(r));
  return out;
}

}  // namespace lhr
