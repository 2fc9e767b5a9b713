// What mesh_surface and default_max_edge (mesh/initial_mesh.hpp) do whatever
// the kind of surface: refuse an h that is not positive, name the surface in
// every meshing error, and size h from the scene.

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <string>

#include "mesh/initial_mesh.hpp"
#include "scene_fixtures.hpp"

namespace lhr {
namespace {

using namespace test;

TEST(MeshingErrors, DegenerateAndCrossingPolygonsNameTheSurface) {
  const Surface collinear =
      make_surface("flat_line", {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}}, {{0, 1, 2}}, true);
  Surface flat = collinear;
  flat.normal = Vec3(0, 0, 1);
  Surface bowtie = make_surface("bowtie", {{0, 0, 0}, {1, 1, 0}, {1, 0, 0}, {0, 1, 0}}, {{0, 1, 2, 3}}, true);
  bowtie.normal = Vec3(0, 0, 1);
  for (const Surface& s : {flat, bowtie}) {
    try {
      mesh_surface(s, with_h(0.1));
      ADD_FAILURE() << s.name << " was meshed";
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find("surface '" + s.name + "'"), std::string::npos) << e.what();
    }
  }
  EXPECT_THROW(mesh_surface(unit_square(), with_h(0.0)), std::invalid_argument);
  EXPECT_THROW(mesh_surface(unit_square(), with_h(std::nan(""))), std::invalid_argument);
}

TEST(MeshingDefaults, MaxEdgeIsATwentiethOfTheDiagonal) {
  Scene scene;
  scene.surfaces.push_back(make_surface("a", {{0, 0, 0}, {3, 0, 0}, {3, 4, 0}}, {{0, 1, 2}}, true));
  scene.surfaces.push_back(make_surface("b", {{0, 0, 12}, {1, 0, 12}, {1, 1, 12}}, {{0, 1, 2}}, true));
  EXPECT_DOUBLE_EQ(default_max_edge(scene), 13.0 / 20.0);
  EXPECT_THROW(default_max_edge(Scene{}), std::runtime_error);
}

}  // namespace
}  // namespace lhr
