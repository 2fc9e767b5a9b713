#pragma once
// Deterministic sample patterns: every pattern is a pure function of a key
// built from element ids, so results do not depend on thread order.

#include <array>
#include <cstdint>
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
