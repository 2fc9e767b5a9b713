#pragma once
// RGB triple of linear quantities: reflectance, radiance, irradiance, display
// colour.
//
// A type of its own, not OpenMesh::Vec3d like Vec3: with one type for both, a
// radiance passed where a position or a normal was expected, and the other way
// round, without a word from the compiler. There is deliberately no conversion
// to or from Vec3, not even an explicit one: nothing in lhr turns a position
// into a colour, and whatever must will write it out channel by channel.
//
// Only the arithmetic colours need is here. Each operation computes what
// OpenMesh's vector did, channel by channel in the same order (a / s divides,
// it does not multiply by 1/s), so the solvers' numbers did not change when
// colours stopped being Vec3. Geometric operations (dot, cross, norm) are left
// out on purpose: a Euclidean norm of a colour difference is no measure of
// colour; code that wants "how far apart" says which (e.g. the largest
// channel difference).

#include <cstddef>
#include <ostream>

namespace lhr {

struct Rgb {
  double channel[3]{};  // r, g, b

  constexpr Rgb() = default;  // black: every channel zero, never indeterminate
  constexpr Rgb(double r, double g, double b) : channel{r, g, b} {}

  constexpr double& operator[](std::size_t i) { return channel[i]; }
  constexpr const double& operator[](std::size_t i) const { return channel[i]; }

  constexpr Rgb& operator+=(const Rgb& o) {
    for (std::size_t i = 0; i < 3; ++i) channel[i] += o.channel[i];
    return *this;
  }
  constexpr Rgb& operator-=(const Rgb& o) {
    for (std::size_t i = 0; i < 3; ++i) channel[i] -= o.channel[i];
    return *this;
  }
  constexpr Rgb& operator*=(double s) {
    for (double& c : channel) c *= s;
    return *this;
  }
  constexpr Rgb& operator/=(double s) {
    for (double& c : channel) c /= s;
    return *this;
  }

  // Exact, channel by channel: tests compare colours read back from files.
  friend constexpr bool operator==(const Rgb&, const Rgb&) = default;
};

constexpr Rgb operator+(Rgb a, const Rgb& b) { return a += b; }
constexpr Rgb operator-(Rgb a, const Rgb& b) { return a -= b; }
constexpr Rgb operator*(Rgb a, double s) { return a *= s; }
constexpr Rgb operator*(double s, Rgb a) { return a *= s; }
constexpr Rgb operator/(Rgb a, double s) { return a /= s; }

// Channel-wise product: a reflectance filtering a radiance or irradiance.
constexpr Rgb operator*(const Rgb& a, const Rgb& b) { return Rgb(a[0] * b[0], a[1] * b[1], a[2] * b[2]); }

// The largest channel: whether a surface reflects at all, and how likely a
// path survives Russian roulette. Compared as std::max_element compares (the
// first of equal channels wins, a NaN in channel 0 is kept), as OpenMesh's
// max() did, so both decide as before.
constexpr double max_channel(const Rgb& c) {
  double m = c[0];
  if (m < c[1]) m = c[1];
  if (m < c[2]) m = c[2];
  return m;
}

// Space-separated like OpenMesh's vectors, so messages and test failures read
// the same as before.
inline std::ostream& operator<<(std::ostream& os, const Rgb& c) { return os << c[0] << ' ' << c[1] << ' ' << c[2]; }

}  // namespace lhr
