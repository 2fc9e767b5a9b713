// Directions drawn uniformly over the solid angle of a triangle (Arvo's
// construction) against closed forms: the solid angle of an octant and of a
// rectangle on its axis, the share of directions each quarter of a triangle
// receives, and the exact point-to-triangle form factor.

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <vector>

#include "radiosity/form_factor.hpp"
#include "radiosity/sampling.hpp"

namespace lhr {
namespace {

using Triangle = std::array<Vec3, 3>;

TEST(SolidAngle, OctantRectangleAndPlaneAgreeWithClosedForms) {
  // The triangle of the three unit axes is an eighth of the sphere from the origin.
  EXPECT_NEAR(triangle_solid_angle(Vec3(0, 0, 0), {Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)}), M_PI / 2, 1e-12);
  // A 2a × 2b rectangle at distance d on its axis: 4 asin(ab / √((a²+d²)(b²+d²))).
  const double a = 0.7, b = 1.9, d = 0.3;
  const Vec3 x(0, 0, d);
  const Vec3 p0(-a, -b, 0), p1(a, -b, 0), p2(a, b, 0), p3(-a, b, 0);
  const double omega = triangle_solid_angle(x, {p0, p1, p2}) + triangle_solid_angle(x, {p0, p2, p3});
  EXPECT_NEAR(omega, 4.0 * std::asin(a * b / std::sqrt((a * a + d * d) * (b * b + d * d))), 1e-12);
  // On the triangle's plane it subtends nothing; either side gives the same.
  EXPECT_NEAR(triangle_solid_angle(Vec3(5, 5, 0), {p0, p1, p2}), 0.0, 1e-15);
  EXPECT_NEAR(triangle_solid_angle(Vec3(0.1, 0.2, -d), {p0, p1, p2}),
              triangle_solid_angle(Vec3(0.1, 0.2, d), {p0, p1, p2}), 1e-14);
}

// Where the direction from x meets the triangle's plane, as barycentric weights.
std::array<double, 3> barycentric_hit(const Vec3& x, const Vec3& direction, const Triangle& t) {
  const Vec3 n = OpenMesh::cross(t[1] - t[0], t[2] - t[0]);
  const double along = OpenMesh::dot(n, t[0] - x) / OpenMesh::dot(n, direction);
  const Vec3 y = x + along * direction;
  const double area2 = n.sqrnorm();
  const double w1 = OpenMesh::dot(OpenMesh::cross(y - t[0], t[2] - t[0]), n) / area2;  // weight of t[1]
  const double w2 = OpenMesh::dot(OpenMesh::cross(t[1] - t[0], y - t[0]), n) / area2;  // weight of t[2]
  return {1.0 - w1 - w2, w1, w2};
}

// Triangles seen from x near and far, skewed, from either side, and with x
// just off an edge: where drawing by area and weighing by the kernel goes wrong.
struct Case {
  Vec3 x;
  Triangle t;
};
const std::vector<Case> kCases{
    {Vec3(0.2, 0.3, 1.0), {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)}},
    {Vec3(0.2, 0.3, 0.01), {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)}},
    {Vec3(-0.4, 0.0, 0.05), {Vec3(0, 0, 0), Vec3(4, 0.2, 0), Vec3(0.1, 0.3, 0)}},
    {Vec3(0.5, -0.001, 0.002), {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0.5, 2, 0)}},
    {Vec3(30, 40, 50), {Vec3(0, 0, 0), Vec3(0, 1, 0), Vec3(1, 0, 0)}},
    {Vec3(1, 2, -3), {Vec3(0, 0, 0), Vec3(2, 0, 1), Vec3(0, 2, 1)}},
};

TEST(SphericalTriangleSample, EveryDirectionMeetsTheTriangleAndEachQuarterGetsItsShare) {
  constexpr int kDraws = 40000;
  for (const Case& c : kCases) {
    const Triangle& t = c.t;
    const double omega = triangle_solid_angle(c.x, t);
    const SphericalTriangle spherical(c.x, t);
    ASSERT_TRUE(spherical.valid()) << "x " << c.x;
    EXPECT_NEAR(spherical.solid_angle(), omega, 1e-15 + 1e-12 * omega);
    // The triangle cut at its edges' midpoints: a uniform draw lands in each
    // quarter in proportion to the quarter's own solid angle.
    const Vec3 m01 = 0.5 * (t[0] + t[1]), m12 = 0.5 * (t[1] + t[2]), m20 = 0.5 * (t[2] + t[0]);
    const std::array<Triangle, 4> quarters{Triangle{t[0], m01, m20}, Triangle{m01, t[1], m12},
                                           Triangle{m20, m12, t[2]}, Triangle{m01, m12, m20}};
    std::array<int, 4> landed{0, 0, 0, 0};
    for (int i = 0; i < kDraws; ++i) {
      const auto direction = spherical.sample(unit_double(sample_key(1, i)), unit_double(sample_key(2, i)));
      ASSERT_TRUE(direction) << "x " << c.x;
      EXPECT_NEAR(direction->norm(), 1.0, 1e-12);
      const auto w = barycentric_hit(c.x, *direction, t);
      for (double wk : w) ASSERT_GT(wk, -1e-7) << "x " << c.x << ", draw " << i;
      // Quarter by quarter: the corner quarters are where each weight exceeds
      // one half, the middle one where none does.
      int q = 3;
      for (int k = 0; k < 3; ++k) {
        if (w[k] > 0.5) q = k;
      }
      ++landed[q];
    }
    for (int q = 0; q < 4; ++q) {
      const double p = triangle_solid_angle(c.x, quarters[q]) / omega;
      const double sigma = std::sqrt(p * (1 - p) / kDraws);
      EXPECT_NEAR(static_cast<double>(landed[q]) / kDraws, p, 4.5 * sigma + 1e-9)
          << "x " << c.x << ", quarter " << q;
    }
  }
}

TEST(SphericalTriangleSample, CosineTimesSolidAngleOverPiAveragesToTheFormFactor) {
  constexpr int kDraws = 40000;
  for (const Case& c : kCases) {
    // The receiver's normal faces the triangle's centroid, tilted so that
    // cos θx varies across it.
    const Vec3 centroid = (c.t[0] + c.t[1] + c.t[2]) / 3.0;
    const Vec3 n = ((centroid - c.x).normalized() + Vec3(0.2, -0.1, 0.15)).normalized();
    const SphericalTriangle spherical(c.x, c.t);
    double sum = 0.0, sum2 = 0.0;
    for (int i = 0; i < kDraws; ++i) {
      const auto direction = spherical.sample(unit_double(sample_key(3, i)), unit_double(sample_key(4, i)));
      ASSERT_TRUE(direction);
      const double f = std::max(0.0, OpenMesh::dot(n, *direction)) * spherical.solid_angle() / M_PI;
      sum += f;
      sum2 += f * f;
    }
    const double mean = sum / kDraws, sigma = std::sqrt(std::max(0.0, sum2 / kDraws - mean * mean) / kDraws);
    // The exact form factor takes the triangle from its front; from its back
    // the same integral is the mirror triangle's.
    const Vec3 tn = OpenMesh::cross(c.t[1] - c.t[0], c.t[2] - c.t[0]);
    const Triangle front = OpenMesh::dot(tn, c.x - c.t[0]) > 0 ? c.t : Triangle{c.t[0], c.t[2], c.t[1]};
    const double exact = point_triangle_form_factor(c.x, n, front);
    ASSERT_GT(exact, 0.0);
    EXPECT_NEAR(mean, exact, 4.5 * sigma + 1e-12) << "x " << c.x;
  }
}

TEST(SphericalTriangleSample, TinyOrDegenerateTrianglesAreLeftToDrawingByArea) {
  const Triangle t{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
  EXPECT_FALSE(SphericalTriangle(Vec3(0.3, 0.3, 0), t).sample(0.5, 0.5));  // on its plane
  EXPECT_FALSE(SphericalTriangle(Vec3(0, 0, 0), t).sample(0.5, 0.5));      // at a corner
  EXPECT_FALSE(SphericalTriangle(Vec3(0, 0, 1e6), t).sample(0.5, 0.5));    // 1e-12 sr
  EXPECT_TRUE(SphericalTriangle(Vec3(0, 0, 1e4), t).sample(0.5, 0.5));     // 5e-9 sr
}

}  // namespace
}  // namespace lhr
