// Surface splitting (docs/design.md §3): which faces of a polygon soup form
// one surface, and what each surface records about its neighbours.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "mesh/surfaces.hpp"

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

}  // namespace
}  // namespace lhr
