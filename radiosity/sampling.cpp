#include "radiosity/sampling.hpp"

#include <cmath>

namespace lhr {

std::vector<TriangleSample> stratified_triangle_samples(int k, std::uint64_t key) {
  std::vector<TriangleSample> samples;
  stratified_triangle_samples(k, key, samples);
  return samples;
}

void stratified_triangle_samples(int k, std::uint64_t key, std::vector<TriangleSample>& samples) {
  samples.clear();
  if (k <= 0) return;
  samples.reserve(static_cast<std::size_t>(k) * k);
  const double step = 1.0 / k;
  int index = 0;
  // In (s,t) coordinates (barycentric weights of corners 1 and 2) the
  // triangle s,t ≥ 0, s+t ≤ 1 is tiled by k² half-cells: an upright one at
  // (i,j) for i+j < k, and an inverted one for i+j < k−1.
  for (int i = 0; i < k; ++i) {
    for (int j = 0; i + j < k; ++j) {
      for (int inverted = 0; inverted < 2; ++inverted) {
        if (inverted && i + j >= k - 1) continue;
        double a = unit_double(sample_key(key, index, 1));
        double b = unit_double(sample_key(key, index, 2));
        ++index;
        if (a + b > 1.0) {  // fold the unit square onto the triangle: uniform by area
          a = 1.0 - a;
          b = 1.0 - b;
        }
        double s, t;
        if (!inverted) {
          s = (i + a) * step;
          t = (j + b) * step;
        } else {
          s = (i + 1 - a) * step;
          t = (j + 1 - b) * step;
        }
        samples.push_back({{1.0 - s - t, s, t}});
      }
    }
  }
}

TriangleSample uniform_triangle_sample(std::uint64_t key) {
  double s = unit_double(sample_key(key, 0, 1));
  double t = unit_double(sample_key(key, 0, 2));
  if (s + t > 1.0) {
    s = 1.0 - s;
    t = 1.0 - t;
  }
  return {{1.0 - s - t, s, t}};
}

std::vector<Vec3> hemisphere_probe_directions(const Vec3& n) {
  constexpr int kRings = 4, kSectors = 8;
  const Vec3 t =
      (std::abs(n[0]) < 0.9 ? OpenMesh::cross(n, Vec3(1, 0, 0)) : OpenMesh::cross(n, Vec3(0, 1, 0))).normalized();
  const Vec3 b = OpenMesh::cross(n, t);
  std::vector<Vec3> directions;
  directions.reserve(kRings * kSectors);
  for (int i = 0; i < kRings; ++i) {
    const double r = std::sqrt((i + 0.5) / kRings);
    for (int j = 0; j < kSectors; ++j) {
      const double phi = 2.0 * M_PI * (j + 0.5 * (i % 2)) / kSectors;
      directions.push_back(r * std::cos(phi) * t + r * std::sin(phi) * b + std::sqrt(1.0 - r * r) * n);
    }
  }
  return directions;
}

}  // namespace lhr
