// Rgb (mesh/rgb.hpp): its arithmetic, that it gives the numbers OpenMesh's
// Vec3d gave when colours were Vec3 (so the solvers' results did not move),
// and that a colour and a position no longer mix.

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <sstream>
#include <type_traits>

#include "mesh/types.hpp"

namespace lhr {
namespace {

// --- a colour is not a position ----------------------------------------------

template <typename A, typename B>
concept Addable = requires(A a, B b) { a + b; };
template <typename A, typename B>
concept Subtractable = requires(A a, B b) { a - b; };
template <typename A, typename B>
concept Multipliable = requires(A a, B b) { a * b; };
template <typename A, typename B>
concept Comparable = requires(A a, B b) { a == b; };

// The checks bite: each operation exists within one type.
static_assert(Addable<Rgb, Rgb> && Subtractable<Rgb, Rgb> && Multipliable<Rgb, Rgb> && Comparable<Rgb, Rgb>);
static_assert(Addable<Vec3, Vec3> && Subtractable<Vec3, Vec3> && Multipliable<Vec3, Vec3> && Comparable<Vec3, Vec3>);

static_assert(!std::is_convertible_v<Vec3, Rgb>);
static_assert(!std::is_convertible_v<Rgb, Vec3>);
static_assert(!std::is_constructible_v<Rgb, Vec3>);
static_assert(!std::is_constructible_v<Vec3, Rgb>);
static_assert(!std::is_assignable_v<Rgb&, Vec3>);
static_assert(!std::is_assignable_v<Vec3&, Rgb>);
static_assert(!Addable<Rgb, Vec3> && !Addable<Vec3, Rgb>);
static_assert(!Subtractable<Rgb, Vec3> && !Subtractable<Vec3, Rgb>);
static_assert(!Multipliable<Rgb, Vec3> && !Multipliable<Vec3, Rgb>);
static_assert(!Comparable<Rgb, Vec3>);
// One number is not a grey: Rgb(0.0) no longer means black by accident.
static_assert(!std::is_convertible_v<double, Rgb>);
static_assert(!std::is_constructible_v<Rgb, double>);

// Same size as Vec3d, which the memory statistics (sizeof(Rgb)) rely on.
static_assert(sizeof(Rgb) == 3 * sizeof(double));
static_assert(std::is_trivially_copyable_v<Rgb>);

// Usable in constant expressions.
static_assert(Rgb() == Rgb(0, 0, 0));
static_assert(Rgb(1, 2, 3) + Rgb(4, 5, 6) == Rgb(5, 7, 9));
static_assert(2.0 * Rgb(1, 2, 3) / 4.0 == Rgb(0.5, 1, 1.5));
static_assert(max_channel(Rgb(1, 3, 2)) == 3);

// The one place a colour becomes a Vec3 on purpose: to hold Rgb's results
// against the OpenMesh arithmetic colours went through when they were Vec3.
Vec3 as_vec3(const Rgb& c) { return Vec3(c[0], c[1], c[2]); }

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof(double)) == 0; }

// --- arithmetic ----------------------------------------------------------------

TEST(Rgb, DefaultIsBlackAndChannelsIndexInOrder) {
  const Rgb black;
  for (int c = 0; c < 3; ++c) EXPECT_EQ(black[c], 0.0);
  Rgb c(0.25, 0.5, 0.75);
  EXPECT_EQ(c[0], 0.25);
  EXPECT_EQ(c[1], 0.5);
  EXPECT_EQ(c[2], 0.75);
  c[1] = 8.0;
  EXPECT_EQ(c, Rgb(0.25, 8.0, 0.75));
  EXPECT_NE(c, Rgb(0.25, 0.5, 0.75));
}

TEST(Rgb, SumsAndDifferencesAreChannelByChannel) {
  const Rgb a(1.5, -2.0, 4.0), b(0.5, 3.0, -1.0);
  EXPECT_EQ(a + b, Rgb(2.0, 1.0, 3.0));
  EXPECT_EQ(a - b, Rgb(1.0, -5.0, 5.0));
  Rgb c = a;
  c += b;
  EXPECT_EQ(c, Rgb(2.0, 1.0, 3.0));
  c -= b;
  EXPECT_EQ(c, a);
  EXPECT_EQ(&(c += b), &c);  // chains like the built-in operators
}

TEST(Rgb, ScalingMultipliesOrDividesEveryChannel) {
  const Rgb a(1.0, -2.0, 6.0);
  EXPECT_EQ(3.0 * a, Rgb(3.0, -6.0, 18.0));
  EXPECT_EQ(a * 3.0, 3.0 * a);
  EXPECT_EQ(a / 4.0, Rgb(0.25, -0.5, 1.5));
  Rgb c = a;
  c *= 0.5;
  EXPECT_EQ(c, Rgb(0.5, -1.0, 3.0));
  c /= 2.0;
  EXPECT_EQ(c, Rgb(0.25, -0.5, 1.5));
}

TEST(Rgb, DivisionDividesRatherThanMultiplyingByTheReciprocal) {
  // 5 / 3 and 5 * (1 / 3) differ in the last bit; OpenMesh divided.
  ASSERT_NE(5.0 / 3.0, 5.0 * (1.0 / 3.0));
  EXPECT_EQ((Rgb(5, 5, 5) / 3.0)[0], 5.0 / 3.0);
  Rgb c(5, 7, 10);
  c /= 3.0;
  EXPECT_EQ(c, Rgb(5.0 / 3.0, 7.0 / 3.0, 10.0 / 3.0));
}

TEST(Rgb, ProductOfTwoColoursIsChannelByChannel) {
  const Rgb reflectance(0.5, 0.25, 0.0), radiance(4.0, 8.0, 100.0);
  EXPECT_EQ(reflectance * radiance, Rgb(2.0, 2.0, 0.0));
  EXPECT_EQ(radiance * reflectance, reflectance * radiance);
}

TEST(Rgb, LargestChannel) {
  EXPECT_EQ(max_channel(Rgb(0.1, 0.7, 0.3)), 0.7);
  EXPECT_EQ(max_channel(Rgb(0.9, 0.7, 0.3)), 0.9);
  EXPECT_EQ(max_channel(Rgb(0.1, 0.7, 3.0)), 3.0);
  EXPECT_EQ(max_channel(Rgb(-1, -2, -0.5)), -0.5);
  EXPECT_EQ(max_channel(Rgb(2, 2, 2)), 2.0);
  EXPECT_EQ(max_channel(Rgb()), 0.0);
}

TEST(Rgb, LargestChannelOfNaNsAndSignedZerosIsWhatOpenMeshGave) {
  // NaN included: the solvers and the path tracer test `max_channel(c) > 0`
  // and must decide as before.
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  const Rgb cases[] = {Rgb(nan, 1, 2), Rgb(1, nan, 2), Rgb(1, 2, nan), Rgb(nan, nan, nan),
                       Rgb(inf, 1, -inf), Rgb(-0.0, 0.0, -0.0), Rgb(0.0, -0.0, 0.0)};
  // Spelled out for two of them: a NaN first is kept, a NaN later skipped.
  EXPECT_TRUE(std::isnan(max_channel(Rgb(nan, 1, 2))));
  EXPECT_EQ(max_channel(Rgb(1, nan, 0.5)), 1.0);
  for (const Rgb& c : cases) {
    EXPECT_TRUE(same_bits(max_channel(c), as_vec3(c).max())) << c;
  }
}

TEST(Rgb, PrintsItsChannelsSpaceSeparated) {
  std::ostringstream out;
  out << Rgb(0.5, 2, -1);
  EXPECT_EQ(out.str(), "0.5 2 -1");
}

// --- the same numbers as Vec3d ---------------------------------------------------

void expect_bit_identical(const Rgb& got, const Vec3& want) {
  for (int c = 0; c < 3; ++c) {
    EXPECT_TRUE(same_bits(got[c], want[c])) << got << " against " << want << ", channel " << c;
  }
}

TEST(Rgb, ArithmeticIsBitIdenticalToOpenMeshVec3d) {
  std::mt19937_64 random(20240611);
  std::uniform_real_distribution<double> value(-1e3, 1e3);
  const auto random_rgb = [&] { return Rgb(value(random), value(random), value(random)); };
  for (int i = 0; i < 1000; ++i) {
    const Rgb a = random_rgb(), b = random_rgb(), w = random_rgb();
    const double s = value(random);
    const Vec3 va = as_vec3(a), vb = as_vec3(b), vw = as_vec3(w);
    expect_bit_identical(a + b, va + vb);
    expect_bit_identical(a - b, va - vb);
    expect_bit_identical(s * a, s * va);
    expect_bit_identical(a * s, va * s);
    expect_bit_identical(a / s, va / s);
    expect_bit_identical(a * b, va * vb);
    // The shape of the solvers' sums: weights times values, accumulated.
    expect_bit_identical(w[0] * a + w[1] * b - 4.0 * w / s, vw[0] * va + vw[1] * vb - 4.0 * vw / s);
    Rgb acc = a;
    Vec3 vacc = va;
    acc += b, vacc += vb;
    acc -= w, vacc -= vw;
    acc *= s, vacc *= s;
    acc /= 7.0, vacc /= 7.0;
    expect_bit_identical(acc, vacc);
    EXPECT_TRUE(same_bits(max_channel(a), va.max()));
    EXPECT_EQ(a == b, va == vb);
  }
}

}  // namespace
}  // namespace lhr
