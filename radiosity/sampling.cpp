#include "radiosity/sampling.hpp"

#include <algorithm>
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

namespace {

// The part of v across the unit vector a, normalized: the tangent at a of
// the great circle from a toward v.
Vec3 tangent_toward(const Vec3& a, const Vec3& v) {
  const Vec3 t = v - OpenMesh::dot(v, a) * a;
  const double len = t.norm();
  return len > 0 ? t / len : Vec3(0, 0, 0);
}

// The spherical triangle's angle at unit vertex a, between its sides to b
// and c.
double corner_angle(const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 tb = tangent_toward(a, b), tc = tangent_toward(a, c);
  return std::atan2(OpenMesh::cross(tb, tc).norm(), OpenMesh::dot(tb, tc));
}

}  // namespace

double triangle_solid_angle(const Vec3& x, const std::array<Vec3, 3>& t) {
  const Vec3 a = t[0] - x, b = t[1] - x, c = t[2] - x;
  const double la = a.norm(), lb = b.norm(), lc = c.norm();
  const double triple = std::abs(OpenMesh::dot(a, OpenMesh::cross(b, c)));
  const double denominator =
      la * lb * lc + OpenMesh::dot(a, b) * lc + OpenMesh::dot(b, c) * la + OpenMesh::dot(c, a) * lb;
  return 2.0 * std::atan2(triple, denominator);
}

SphericalTriangle::SphericalTriangle(const Vec3& x, const std::array<Vec3, 3>& t) {
  const Vec3 da = t[0] - x, db = t[1] - x, dc = t[2] - x;
  const double la = da.norm(), lb = db.norm(), lc = dc.norm();
  if (!(la > 0 && lb > 0 && lc > 0)) return;
  a_ = da / la;
  b_ = db / lb;
  c_ = dc / lc;
  // Van Oosterom and Strackee on the unit corner directions.
  const double triple = std::abs(OpenMesh::dot(a_, OpenMesh::cross(b_, c_)));
  omega_ = 2.0 * std::atan2(triple, 1.0 + OpenMesh::dot(a_, b_) + OpenMesh::dot(b_, c_) + OpenMesh::dot(c_, a_));
  if (!(omega_ >= kTinySolidAngle)) return;
  toward_c_ = tangent_toward(a_, c_);
  const double alpha = corner_angle(a_, b_, c_);
  alpha_ = alpha;
  sin_alpha_ = std::sin(alpha);
  cos_alpha_ = std::cos(alpha);
  cos_c_ = std::clamp(OpenMesh::dot(a_, b_), -1.0, 1.0);
  valid_ = sin_alpha_ > 0.0;
}

std::optional<Vec3> SphericalTriangle::sample(double u1, double u2) const {
  if (!valid_) return std::nullopt;
  // Arvo's construction: the sub-triangle a-b-ĉ of area u1·Ω, its corner ĉ on
  // the side from a to c, then a point on the arc from b to ĉ whose cosine
  // to b is uniform.
  const double sub_area = u1 * omega_;
  const double s = std::sin(sub_area - alpha_), co = std::cos(sub_area - alpha_);
  const double u = co - cos_alpha_;
  const double v = s + sin_alpha_ * cos_c_;
  const double denominator = (v * s + u * co) * sin_alpha_;
  if (!(std::abs(denominator) > 0)) return std::nullopt;
  const double q = std::clamp(((v * co - u * s) * cos_alpha_ - v) / denominator, -1.0, 1.0);
  const Vec3 c_hat = q * a_ + std::sqrt(std::max(0.0, 1.0 - q * q)) * toward_c_;
  const double z = 1.0 - u2 * (1.0 - OpenMesh::dot(c_hat, b_));
  const Vec3 direction = z * b_ + std::sqrt(std::max(0.0, 1.0 - z * z)) * tangent_toward(b_, c_hat);
  const double len = direction.norm();
  if (!(len > 0)) return std::nullopt;
  return direction / len;
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
