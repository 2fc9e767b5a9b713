// Surface splitting (docs/design.md §3): which faces of a polygon soup form
// one surface, and what each surface records about its neighbours.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "mesh/surfaces.hpp"
#include "scene_fixtures.hpp"

namespace lhr {
namespace {

TEST(SurfaceSplit, InconsistentlyOrientedNeighboursAreSeparate) {
  // Two coplanar triangles sharing an edge, the second one flipped: their
  // front sides differ by 180°, so they cannot share radiance.
  PolygonSoup soup;
  soup.points = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  soup.materials = {Material{}};
  soup.groups = {"g"};
  soup.faces = {{{0, 1, 2}, 0, 0, 1}, {{0, 3, 2}, 0, 0, 2}};
  const SurfaceSplit split = split_into_surfaces(soup, 30.0);
  ASSERT_EQ(split.surfaces.size(), 2u);
  EXPECT_NEAR(split.surfaces[0].normal[2], 1.0, 1e-12);
  EXPECT_NEAR(split.surfaces[1].normal[2], -1.0, 1e-12);
  EXPECT_EQ(split_into_surfaces(soup, 180.0).surfaces.size(), 1u);
}

TEST(SurfaceSplit, EachSurfaceRecordsTheEdgesItSharesWithAnother) {
  // Three triangles of a square strip: the first two share material 0, the
  // third has material 1. Only the edge between the second and the third is
  // a seam, recorded in both surfaces with their own point indices.
  PolygonSoup soup;
  soup.points = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {2, 0, 0}};
  soup.materials = {Material{}, Material{}};
  soup.groups = {"g"};
  soup.faces = {{{0, 1, 2}, 0, 0, 1}, {{0, 2, 3}, 0, 0, 2}, {{1, 4, 2}, 1, 0, 3}};
  const SurfaceSplit split = split_into_surfaces(soup, 30.0);
  ASSERT_EQ(split.surfaces.size(), 2u);
  for (const Surface& s : split.surfaces) {
    ASSERT_EQ(s.seam_edges.size(), 1u) << s.name;
    const Vec3 a = s.points[s.seam_edges[0].first], b = s.points[s.seam_edges[0].second];
    EXPECT_EQ(std::min(a[1], b[1]), 0.0);
    EXPECT_EQ(std::max(a[1], b[1]), 1.0);
    EXPECT_EQ(a[0], 1.0);
    EXPECT_EQ(b[0], 1.0);
  }
}

TEST(SurfaceSplit, SlightlyBentSurfaceIsNotPlanar) {
  // Two triangles folded by 2° along their shared edge: one surface at the
  // default crease angle, but not planar.
  const double bend = 2.0 * M_PI / 180.0;
  PolygonSoup soup;
  soup.points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {-std::cos(bend), 0, std::sin(bend)}};
  soup.materials = {Material{}};
  soup.groups = {"g"};
  soup.faces = {{{0, 1, 2}, 0, 0, 1}, {{0, 2, 3}, 0, 0, 2}};
  const SurfaceSplit split = split_into_surfaces(soup, 30.0);
  ASSERT_EQ(split.surfaces.size(), 1u);
  EXPECT_FALSE(split.surfaces[0].planar);
  EXPECT_EQ(split_into_surfaces(soup, 1.0).surfaces.size(), 2u);
}

TEST(SurfaceSplit, CoplanarPiecesOfALightThatReflectsNothingShootAsOneSurface) {
  // Unit squares, none touching another. Four lamps (material 0: emits,
  // reflects nothing) at z = 2 facing down, in group 0, join into one planar
  // surface. Each of the others differs from them in one way and stays a
  // surface of its own: a lamp 10⁻³ higher, a lamp facing up, a lamp of
  // group 1, and two coplanar pieces of a light that also reflects
  // (material 1), which would receive and must stay continuous per piece.
  PolygonSoup soup;
  Material lamp, glowing;
  lamp.reflectance = Rgb(0, 0, 0);
  lamp.emission = Rgb(1, 1, 1);
  glowing.reflectance = Rgb(0.5, 0.5, 0.5);
  glowing.emission = Rgb(1, 1, 1);
  soup.materials = {lamp, glowing};
  soup.groups = {"g", "h"};
  const auto add_square = [&](double x, double y, double z, bool down, int material, int group) {
    const int n = static_cast<int>(soup.points.size());
    soup.points.insert(soup.points.end(), {{x, y, z}, {x + 1, y, z}, {x + 1, y + 1, z}, {x, y + 1, z}});
    std::vector<int> face = down ? std::vector<int>{n, n + 3, n + 2, n + 1} : std::vector<int>{n, n + 1, n + 2, n + 3};
    soup.faces.push_back({face, material, group, static_cast<int>(soup.faces.size()) + 1});
  };
  for (int i = 0; i < 4; ++i) add_square(2.0 * i, 0, 2, true, 0, 0);
  add_square(0, 4, 2.001, true, 0, 0);
  add_square(2, 4, 2, false, 0, 0);
  add_square(4, 4, 2, true, 0, 1);
  add_square(0, 8, 2, true, 1, 0);
  add_square(2, 8, 2, true, 1, 0);
  const SurfaceSplit split = split_into_surfaces(soup, 30.0);
  ASSERT_EQ(split.surfaces.size(), 6u);
  const Surface& panel = split.surfaces[0];
  EXPECT_EQ(panel.polygons.size(), 4u);
  EXPECT_EQ(panel.points.size(), 16u);
  EXPECT_TRUE(panel.planar);
  EXPECT_NEAR(panel.normal[2], -1.0, 1e-12);
  EXPECT_NEAR(panel.area, 4.0, 1e-12);
  for (std::size_t s = 1; s < split.surfaces.size(); ++s) {
    EXPECT_EQ(split.surfaces[s].polygons.size(), 1u) << split.surfaces[s].name;
    EXPECT_TRUE(split.surfaces[s].planar) << split.surfaces[s].name;
  }
}

// A soup of 10^6 faces takes a second to split: the split calls the
// checkpoint every few thousand faces and edges, and what it throws ends
// the split (docs/robustness.md, "Interrupted runs").
TEST(SurfaceSplit, ALargeSoupCallsTheCheckpointAndWhatItThrowsEndsTheSplit) {
  constexpr int kSide = 100;
  const PolygonSoup soup = test::grid_soup(kSide);
  int calls = 0;
  const SurfaceSplit split = split_into_surfaces(soup, 30.0, [&] { ++calls; });
  EXPECT_EQ(split.surfaces.size(), 1u);
  // The faces are passed over three times, the points and the edges (about
  // 1.5 per face) twice.
  const int faces = static_cast<int>(soup.faces.size());
  EXPECT_GE(calls, 3 * (faces / 4096) + kSide * kSide / 4096 + 2 * (3 * faces / 2 / 4096));
  struct Stop {};
  for (const int stop_at : {1, calls / 2, calls}) {
    int seen = 0;
    EXPECT_THROW(split_into_surfaces(soup, 30.0,
                                     [&] {
                                       if (++seen == stop_at) throw Stop{};
                                     }),
                 Stop);
    EXPECT_EQ(seen, stop_at) << "nothing ran the checkpoint after it threw";
  }
}

}  // namespace
}  // namespace lhr
