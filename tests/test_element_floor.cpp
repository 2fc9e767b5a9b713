// The smallest elements refinement may make (radiosity/element_floor.hpp):
// h/32 for the scene, finer toward a small partner, and finer on a thin
// surface of its own, which must hold its bends across its width
// (docs/accuracy.md, "Thin parts").

#include <gtest/gtest.h>

#include <cmath>

#include "mesh/initial_mesh.hpp"
#include "radiosity/element_floor.hpp"
#include "scene_fixtures.hpp"

namespace lhr {
namespace {

double area_of_edge(double edge) { return std::sqrt(3.0) / 4.0 * edge * edge; }

// A 4 x 2.7 wall, and in front of it a chair leg's face: 4 cm by 41 cm.
Scene wall_and_leg() {
  PolygonSoup soup;
  soup.materials = {test::grey_material("wall", 0.6), test::grey_material("wood", 0.5)};
  soup.groups = {"wall", "leg"};
  test::add_quad(soup, Vec3(0, 0, 0), Vec3(4, 0, 0), Vec3(4, 2.7, 0), Vec3(0, 2.7, 0), 0, 0);
  test::add_quad(soup, Vec3(1, 0, 1), Vec3(1.04, 0, 1), Vec3(1.04, 0.41, 1), Vec3(1, 0.41, 1), 1, 1);
  return test::scene_from_soup(soup, "wall and leg");
}

TEST(ElementFloor, AThinSurfacesElementsMayGoDownToAnEighthOfItsWidth) {
  const Scene scene = wall_and_leg();
  MeshingOptions meshing;
  meshing.max_edge = default_max_edge(scene);
  const MeshedScene model(scene, meshing);
  ASSERT_EQ(model.num_surfaces(), 2);
  const ElementFloor floor(model, 0.0);
  const double scene_floor = area_of_edge(model.max_edge() / 32.0);
  // The wall is wider than the scene floor allows for: h/32.
  EXPECT_DOUBLE_EQ(floor.own_min_area(0), scene_floor);
  // The leg: its width 2A/P = 2 (0.04 · 0.41) / 0.9, over 8.
  const double width = 2.0 * 0.04 * 0.41 / (2.0 * (0.04 + 0.41));
  EXPECT_NEAR(floor.own_min_area(1), area_of_edge(width / 8.0), 1e-12);
  ASSERT_LT(floor.own_min_area(1), scene_floor);
  // Either end's floor lets the leg's own elements go finer, whatever the
  // partner, and leaves the wall's where they were.
  const double leg_element = 4.5 * floor.own_min_area(1);
  EXPECT_TRUE(floor.allows_split(leg_element, 1, 0));
  EXPECT_TRUE(floor.allows_split(leg_element, 1, 1));
  EXPECT_FALSE(floor.allows_split(3.5 * floor.own_min_area(1), 1, 0));
  EXPECT_FALSE(floor.allows_split(3.5 * scene_floor, 0, 0));
  EXPECT_TRUE(floor.allows_split(4.5 * scene_floor, 0, 0));
}

TEST(ElementFloor, TheUsersFloorHoldsForThinSurfacesToo) {
  const Scene scene = wall_and_leg();
  MeshingOptions meshing;
  meshing.max_edge = default_max_edge(scene);
  const MeshedScene model(scene, meshing);
  const ElementFloor floor(model, 0.02);
  EXPECT_DOUBLE_EQ(floor.own_min_area(0), area_of_edge(0.02));
  EXPECT_DOUBLE_EQ(floor.own_min_area(1), area_of_edge(0.02));
}

TEST(ElementFloor, AClosedSurfaceHasNoWidthToBoundIt) {
  const Scene scene = test::furnace_sphere();
  MeshingOptions meshing;
  meshing.max_edge = default_max_edge(scene);
  const MeshedScene model(scene, meshing);
  ASSERT_EQ(model.num_surfaces(), 1);
  ASSERT_FALSE(scene.surfaces[0].planar);
  const ElementFloor floor(model, 0.0);
  for (int s = 0; s < model.num_surfaces(); ++s) {
    EXPECT_DOUBLE_EQ(floor.own_min_area(s), area_of_edge(model.max_edge() / 32.0)) << scene.surfaces[s].name;
  }
}

}  // namespace
}  // namespace lhr
