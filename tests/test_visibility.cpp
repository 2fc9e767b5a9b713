// Embree visibility and deterministic sample patterns.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "radiosity/ray_caster.hpp"
#include "radiosity/sampling.hpp"

namespace lhr {
namespace {

TriMesh square(double z, double x0, double x1, double y0, double y1) {
  TriMesh m;
  const auto a = m.add_vertex(Vec3(x0, y0, z)), b = m.add_vertex(Vec3(x1, y0, z));
  const auto c = m.add_vertex(Vec3(x1, y1, z)), d = m.add_vertex(Vec3(x0, y1, z));
  m.add_face(a, b, c);
  m.add_face(a, c, d);
  return m;
}

TEST(Sampling, StratifiedSamplesCoverEveryCellOnceAndStayInside) {
  for (int k : {1, 2, 5, 8}) {
    const auto samples = stratified_triangle_samples(k, 42);
    ASSERT_EQ(samples.size(), static_cast<std::size_t>(k * k));
    for (const auto& s : samples) {
      for (double w : s.barycentric) {
        EXPECT_GE(w, -1e-15);
        EXPECT_LE(w, 1.0 + 1e-15);
      }
      EXPECT_NEAR(s.barycentric[0] + s.barycentric[1] + s.barycentric[2], 1.0, 1e-14);
    }
  }
  // The mean of a uniform pattern is near the centroid.
  const auto many = stratified_triangle_samples(32, 7);
  double mean_s = 0, mean_t = 0;
  for (const auto& s : many) {
    mean_s += s.barycentric[1];
    mean_t += s.barycentric[2];
  }
  EXPECT_NEAR(mean_s / many.size(), 1.0 / 3.0, 1e-3);
  EXPECT_NEAR(mean_t / many.size(), 1.0 / 3.0, 1e-3);
}

TEST(Sampling, PatternsArePureFunctionsOfTheKey) {
  const auto a = stratified_triangle_samples(4, sample_key(3, 9));
  const auto b = stratified_triangle_samples(4, sample_key(3, 9));
  const auto c = stratified_triangle_samples(4, sample_key(9, 3));
  for (std::size_t i = 0; i < a.size(); ++i) EXPECT_EQ(a[i].barycentric, b[i].barycentric);
  bool differs = false;
  for (std::size_t i = 0; i < a.size(); ++i) differs |= a[i].barycentric != c[i].barycentric;
  EXPECT_TRUE(differs);
}

TEST(RayCaster, BlockerBetweenParallelSquares) {
  const TriMesh floor = square(0, 0, 1, 0, 1), blocker = square(0.5, 0.25, 0.75, 0.25, 0.75);
  const RayCaster scene({&floor, &blocker});
  const Vec3 up(0, 0, 1);
  EXPECT_TRUE(scene.occluded(scene.lift(Vec3(0.5, 0.5, 0), up), Vec3(0.5, 0.5, 1)));
  EXPECT_FALSE(scene.occluded(scene.lift(Vec3(0.1, 0.1, 0), up), Vec3(0.1, 0.1, 1)));
  // A segment ending before the blocker is clear.
  EXPECT_FALSE(scene.occluded(scene.lift(Vec3(0.5, 0.5, 0), up), Vec3(0.5, 0.5, 0.4)));

  std::vector<ShadowRay> rays;
  for (int i = 0; i < 1000; ++i) {
    const double x = (i + 0.5) / 1000.0;
    rays.push_back({scene.lift(Vec3(x, 0.5, 0), up), Vec3(x, 0.5, 1)});
  }
  std::vector<std::uint8_t> blocked(rays.size());
  scene.occluded(rays, blocked);
  for (std::size_t i = 0; i < rays.size(); ++i) {
    EXPECT_EQ(blocked[i], scene.occluded(rays[i].from, rays[i].to) ? 1 : 0) << i;
    const double x = rays[i].from[0];
    if (std::abs(x - 0.25) > 1e-3 && std::abs(x - 0.75) > 1e-3) {
      EXPECT_EQ(blocked[i], (x > 0.25 && x < 0.75) ? 1 : 0) << x;
    }
  }
}

// A ray's end lifted off its own surface can lie within single precision of
// another one: a point on a wall a hair below the ceiling, reached from below
// at a grazing angle, rounded onto the ceiling's plane and was found
// blocked (a link of the furnace cube lost one ray of sixteen that way). The
// wall and the ceiling meet along an edge, nothing lies between.
TEST(RayCaster, AnEndJustBelowAnotherSurfaceIsNotBlockedByIt) {
  TriMesh wall = square(1.0, 0, 1, 0, 1);  // z = 1, spanning x and y in [0, 1]
  TriMesh ceiling;
  {
    const auto a = ceiling.add_vertex(Vec3(0, 1, 0)), b = ceiling.add_vertex(Vec3(1, 1, 0));
    const auto c = ceiling.add_vertex(Vec3(1, 1, 1)), d = ceiling.add_vertex(Vec3(0, 1, 1));
    ceiling.add_face(a, b, c);
    ceiling.add_face(a, c, d);
  }
  const RayCaster scene({&wall, &ceiling});
  std::vector<ShadowRay> rays;
  for (int i = 0; i < 400; ++i) {
    const double x = (i + 0.5) / 400.0;
    for (const double below : {1e-9, 7e-9, 3e-8}) {
      const Vec3 from = scene.lift(Vec3(0.5 * x, 0.875, 0.0), Vec3(0, 0, 1));
      rays.push_back({from, scene.lift(Vec3(x, 1.0 - below, 1.0), Vec3(0, 0, -1))});
    }
  }
  for (const ShadowQuery query : {ShadowQuery::kSingle, ShadowQuery::kStream, ShadowQuery::kPacket4,
                                  ShadowQuery::kPacket8, ShadowQuery::kPacket16}) {
    std::vector<std::uint8_t> blocked(rays.size());
    scene.occluded(rays, blocked, query);
    EXPECT_EQ(std::count(blocked.begin(), blocked.end(), std::uint8_t{1}), 0)
        << "query " << static_cast<int>(query);
  }
  // The gap at the end is a lift's length: a blocker just before it still blocks.
  const TriMesh blocker = square(0.99, 0, 1, 0, 1);
  const RayCaster blocked_scene({&wall, &ceiling, &blocker});
  EXPECT_TRUE(blocked_scene.occluded(rays.front().from, rays.front().to));
}

TEST(RayCaster, EveryBatchQueryAgreesWithSingleRays) {
  // Streams and packets of 4, 8 and 16 on a batch whose size is none of
  // their multiples, mixing clear and blocked segments in every packet.
  const TriMesh floor = square(0, 0, 1, 0, 1), blocker = square(0.5, 0.25, 0.75, 0.25, 0.75);
  const RayCaster scene({&floor, &blocker});
  std::vector<ShadowRay> rays;
  for (std::uint64_t i = 0; i < 1001; ++i) {
    const Vec3 from = scene.lift(Vec3(unit_double(sample_key(i, 1)), unit_double(sample_key(i, 2)), 0), Vec3(0, 0, 1));
    const Vec3 to(unit_double(sample_key(i, 3)), unit_double(sample_key(i, 4)), 0.2 + 0.8 * unit_double(sample_key(i, 5)));
    rays.push_back({from, to});
  }
  std::vector<std::uint8_t> single(rays.size());
  scene.occluded(rays, single, ShadowQuery::kSingle);
  std::size_t blocked = 0;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    ASSERT_EQ(single[i], scene.occluded(rays[i].from, rays[i].to) ? 1 : 0);
    blocked += single[i];
  }
  EXPECT_GT(blocked, 100u);
  EXPECT_LT(blocked, 900u);
  for (ShadowQuery q : {ShadowQuery::kStream, ShadowQuery::kPacket4, ShadowQuery::kPacket8, ShadowQuery::kPacket16}) {
    std::vector<std::uint8_t> out(rays.size(), 7);
    scene.occluded(rays, out, q);
    EXPECT_EQ(out, single) << "query " << static_cast<int>(q);
  }
  std::vector<std::uint8_t> chosen(rays.size(), 7);
  scene.occluded(rays, chosen);
  EXPECT_EQ(chosen, single);
}

TEST(RayCaster, SharedEdgeDoesNotLeak) {
  // Rays through the diagonal shared by the two triangles of a square must hit.
  const TriMesh wall = square(1, 0, 1, 0, 1);
  const RayCaster scene({&wall});
  for (int i = 1; i < 200; ++i) {
    const double t = i / 200.0;
    EXPECT_TRUE(scene.occluded(Vec3(t, t, 0), Vec3(t, t, 2))) << t;
  }
}

TEST(RayCaster, IntersectReportsSurfaceFaceAndDistance) {
  const TriMesh near_square = square(1, 0, 1, 0, 1), far_square = square(3, 0, 1, 0, 1);
  const RayCaster scene({&near_square, &far_square});
  const auto hit = scene.intersect(Vec3(0.8, 0.3, 0), Vec3(0, 0, 1));
  ASSERT_TRUE(hit.has_value());
  EXPECT_EQ(hit->surface, 0);
  EXPECT_EQ(hit->face, 0);
  EXPECT_NEAR(hit->distance, 1.0, 1e-6);
  const auto miss = scene.intersect(Vec3(2, 2, 0), Vec3(0, 0, 1));
  EXPECT_FALSE(miss.has_value());
}

}  // namespace
}  // namespace lhr
