#include "render/vertex_metrics.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "radiosity/tone_map.hpp"

namespace lhr {

namespace {

constexpr double kFloorFraction = 0.01;

double bounding_diagonal(const std::vector<Vec3>& points) {
  if (points.empty()) return 0.0;
  Vec3 lo = points.front(), hi = points.front();
  for (const Vec3& p : points) {
    lo.minimize(p);
    hi.maximize(p);
  }
  return (hi - lo).norm();
}

}  // namespace

double quantile(std::vector<double> values, double q) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  const double at = std::clamp(q, 0.0, 1.0) * static_cast<double>(values.size() - 1);
  const std::size_t below = static_cast<std::size_t>(std::floor(at));
  const std::size_t above = std::min(below + 1, values.size() - 1);
  const double t = at - static_cast<double>(below);
  return values[below] + t * (values[above] - values[below]);
}

VertexMetrics compare_vertex_radiance(const RawMesh& mesh, const RawMesh& reference, double relative_tolerance) {
  const std::size_t n = reference.points.size();
  if (mesh.points.size() != n) {
    throw std::invalid_argument("has " + std::to_string(mesh.points.size()) + " vertices but the reference has " +
                                std::to_string(n) + "; both must be the same mesh");
  }
  if (n == 0) throw std::invalid_argument("has no vertices to compare");
  if (mesh.radiance.size() != n) throw std::invalid_argument("has no radiance_r/g/b vertex values");
  if (reference.radiance.size() != n) throw std::invalid_argument("the reference has no radiance_r/g/b vertex values");
  const double tolerance = relative_tolerance * bounding_diagonal(reference.points);
  for (std::size_t v = 0; v < n; ++v) {
    if (!((mesh.points[v] - reference.points[v]).norm() <= tolerance)) {
      throw std::invalid_argument("vertex " + std::to_string(v) + " is at " + describe_point(mesh.points[v]) +
                                  " but at " + describe_point(reference.points[v]) +
                                  " in the reference; both must be the same mesh");
    }
  }

  VertexMetrics m;
  m.vertices = n;
  std::vector<double> y(n), y_ref(n);
  double sum = 0.0, sum_ref = 0.0;
  for (std::size_t v = 0; v < n; ++v) {
    y[v] = luminance(mesh.radiance[v]);
    y_ref[v] = luminance(reference.radiance[v]);
    if (!std::isfinite(y[v]) || !std::isfinite(y_ref[v])) {
      throw std::invalid_argument("vertex " + std::to_string(v) + " has a radiance that is not a finite number");
    }
    sum += y[v];
    sum_ref += y_ref[v];
  }
  m.floor = kFloorFraction * sum_ref / static_cast<double>(n);
  m.mean_ratio = sum_ref > 0 ? sum / sum_ref : (sum > 0 ? std::numeric_limits<double>::infinity() : 1.0);
  m.has_noise = reference.radiance_stderr.size() == n;

  std::vector<double> errors(n), noise;
  std::size_t within_10 = 0, within_15 = 0, beyond = 0;
  for (std::size_t v = 0; v < n; ++v) {
    const double difference = std::abs(y[v] - y_ref[v]);
    const double denominator = std::max(y_ref[v], m.floor);
    // An all-black reference (floor 0): equal values agree, others are off.
    const double e = denominator > 0 ? difference / denominator
                                     : (difference > 0 ? std::numeric_limits<double>::infinity() : 0.0);
    errors[v] = e;
    within_10 += e <= 0.10;
    within_15 += e <= 0.15;
    if (e > m.max || v == 0) {
      m.max = e;
      m.worst_vertex = v;
    }
    if (m.has_noise) {
      const double se = reference.radiance_stderr[v];
      noise.push_back(denominator > 0 ? se / denominator : 0.0);
      beyond += difference > 3.0 * se;
    }
  }
  m.p50 = quantile(errors, 0.50);
  m.p95 = quantile(errors, 0.95);
  m.within_10 = 100.0 * static_cast<double>(within_10) / static_cast<double>(n);
  m.within_15 = 100.0 * static_cast<double>(within_15) / static_cast<double>(n);
  if (m.has_noise) {
    m.noise_p50 = quantile(noise, 0.50);
    m.beyond_3_sigma = 100.0 * static_cast<double>(beyond) / static_cast<double>(n);
  }
  return m;
}

}  // namespace lhr
