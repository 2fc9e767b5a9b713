#pragma once
// Deterministic sample patterns: every pattern is a pure function of a key
// built from element ids, so results do not depend on thread order.

#include <array>
#include <cstdint>
#include <optional>
#include <vector>

#include "mesh/types.hpp"

namespace lhr {

// splitmix64: a fast, well-mixed hash for keys and per-sample jitter.
constexpr std::uint64_t mix_bits(std::uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

constexpr std::uint64_t sample_key(std::uint64_t a, std::uint64_t b, std::uint64_t c = 0) {
  return mix_bits(mix_bits(mix_bits(a) ^ b) ^ c);
}

// Uniform double in [0,1) from a key.
inline double unit_double(std::uint64_t key) { return static_cast<double>(mix_bits(key) >> 11) * 0x1.0p-53; }

// Barycentric sample (weights of corners 0,1,2) with equal area per sample.
struct TriangleSample {
  std::array<double, 3> barycentric;
};

// k² stratified samples on a triangle: the triangle is cut into k² congruent
// sub-triangles (k cuts per edge) and one sample is jittered uniformly inside
// each, by the key.
std::vector<TriangleSample> stratified_triangle_samples(int k, std::uint64_t key);
// The same samples into `out` (cleared first), for callers that reuse one
// array across calls.
void stratified_triangle_samples(int k, std::uint64_t key, std::vector<TriangleSample>& out);

// One uniform sample, stratified_triangle_samples(1, key)'s, without the
// vector (a shadow ray of a cluster link draws one per ray).
TriangleSample uniform_triangle_sample(std::uint64_t key);

// The solid angle a triangle subtends from x (Van Oosterom and Strackee's
// formula; 0 when x lies on its plane).
double triangle_solid_angle(const Vec3& x, const std::array<Vec3, 3>& t);

// Directions drawn uniformly over the solid angle a triangle subtends from
// x, each from two uniform numbers in [0,1) (Arvo, "Stratified sampling of
// spherical triangles", 1995), with what depends on x and the triangle alone
// worked out once, for many draws (a draw kept with a chance, say). A
// cluster link's shadow rays near the receiver are drawn this way and kept
// with chance cosθx, so that each stands for an equal part of the
// triangle's form factor: points drawn by area and counted alike measure
// its visible share of area instead (docs/accuracy.md, "Under the table,
// light source by light source"). Not valid where the construction loses
// its precision (a solid angle below kTinySolidAngle, x at a corner): there
// the kernel hardly varies over the triangle, and drawing by area is as
// good.
inline constexpr double kTinySolidAngle = 1e-9;
class SphericalTriangle {
 public:
  SphericalTriangle(const Vec3& x, const std::array<Vec3, 3>& t);
  bool valid() const { return valid_; }
  double solid_angle() const { return omega_; }
  // Unit directions from x to the corners.
  const Vec3& a() const { return a_; }
  const Vec3& b() const { return b_; }
  const Vec3& c() const { return c_; }
  // A unit direction from x into the triangle; nullopt where not valid().
  std::optional<Vec3> sample(double u1, double u2) const;

 private:
  Vec3 a_{0, 0, 0}, b_{0, 0, 0}, c_{0, 0, 0}, toward_c_{0, 0, 0};
  double omega_ = 0.0, alpha_ = 0.0, sin_alpha_ = 0.0, cos_alpha_ = 1.0, cos_c_ = 1.0;
  bool valid_ = false;
};

inline Vec3 at(const std::array<Vec3, 3>& t, const TriangleSample& s) {
  return s.barycentric[0] * t[0] + s.barycentric[1] * t[1] + s.barycentric[2] * t[2];
}

// A fixed set of directions over the hemisphere of unit normal n,
// cosine-distributed on a 4 x 8 grid: the probe that tells whether a point
// lies inside a closed object (the back of a face hit first along most of
// them), used alike by the solver and the vertex reference so that both
// take a contact line's value from the same side.
std::vector<Vec3> hemisphere_probe_directions(const Vec3& n);

}  // namespace lhr
