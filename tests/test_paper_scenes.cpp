// The bundled Cornell box and the generated scenes of paper §6: geometry
// invariants, orientation, surface counts and the OBJ/MTL/JSON round trip.

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <limits>
#include <map>
#include <numeric>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include "io/paper_scenes.hpp"
#include "io/scene_writer.hpp"
#include "io/scene_loader.hpp"
#include "mesh/surfaces.hpp"
#include "test_support.hpp"

namespace lhr {
namespace {

constexpr int kTwoRoomsPaperSurfaces = 386;
constexpr int kFourRoomsPaperSurfaces = 296;

std::vector<Vec3> face_points(const PolygonSoup& soup, const InputFace& f) {
  std::vector<Vec3> p;
  for (int v : f.vertices) p.push_back(soup.points.at(v));
  return p;
}

// Newell's method: twice the area vector, exact for planar polygons.
Vec3 area_vector(const std::vector<Vec3>& p) {
  Vec3 n(0, 0, 0);
  for (std::size_t i = 0; i < p.size(); ++i) n += OpenMesh::cross(p[i], p[(i + 1) % p.size()]);
  return 0.5 * n;
}

Vec3 centroid(const std::vector<Vec3>& p) {
  Vec3 c(0, 0, 0);
  for (const Vec3& q : p) c += q;
  return c / static_cast<double>(p.size());
}

Vec3 group_centre(const PolygonSoup& soup, int group) {
  Vec3 lo(1e300, 1e300, 1e300);
  Vec3 hi(-1e300, -1e300, -1e300);
  for (const InputFace& f : soup.faces) {
    if (f.group != group) continue;
    for (int v : f.vertices) {
      lo.minimize(soup.points[v]);
      hi.maximize(soup.points[v]);
    }
  }
  return 0.5 * (lo + hi);
}

int group_index(const PolygonSoup& soup, const std::string& name) {
  const auto it = std::find(soup.groups.begin(), soup.groups.end(), name);
  if (it == soup.groups.end()) throw std::runtime_error("no group " + name);
  return static_cast<int>(it - soup.groups.begin());
}

struct Aabb {
  Vec3 lo{1e300, 1e300, 1e300};
  Vec3 hi{-1e300, -1e300, -1e300};
};

Aabb group_bounds(const PolygonSoup& soup, const std::string& name) {
  const int g = group_index(soup, name);
  Aabb b;
  for (const InputFace& f : soup.faces) {
    if (f.group != g) continue;
    for (int v : f.vertices) {
      b.lo.minimize(soup.points[v]);
      b.hi.maximize(soup.points[v]);
    }
  }
  return b;
}

// Independent count of docs/design.md §3 surfaces: faces of one group and material,
// connected through shared edges (by position) whose normals differ by at
// most the crease angle.
int reference_surface_count(const PolygonSoup& soup, double crease_deg) {
  std::vector<int> parent(soup.faces.size());
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](int i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
  };
  using Key = std::array<double, 3>;
  auto key = [&](int v) { return Key{soup.points[v][0], soup.points[v][1], soup.points[v][2]}; };
  std::map<std::pair<Key, Key>, std::vector<int>> edges;
  for (std::size_t i = 0; i < soup.faces.size(); ++i) {
    const auto& vs = soup.faces[i].vertices;
    for (std::size_t k = 0; k < vs.size(); ++k) {
      Key a = key(vs[k]);
      Key b = key(vs[(k + 1) % vs.size()]);
      if (b < a) std::swap(a, b);
      edges[{a, b}].push_back(static_cast<int>(i));
    }
  }
  const double cos_crease = std::cos(crease_deg * M_PI / 180.0);
  for (const auto& [edge, faces] : edges) {
    for (std::size_t i = 0; i < faces.size(); ++i) {
      for (std::size_t j = i + 1; j < faces.size(); ++j) {
        const InputFace& a = soup.faces[faces[i]];
        const InputFace& b = soup.faces[faces[j]];
        if (a.group != b.group || a.material != b.material) continue;
        const Vec3 na = area_vector(face_points(soup, a)).normalized();
        const Vec3 nb = area_vector(face_points(soup, b)).normalized();
        if (OpenMesh::dot(na, nb) >= cos_crease) parent[find(faces[i])] = find(faces[j]);
      }
    }
  }
  int roots = 0;
  for (std::size_t i = 0; i < parent.size(); ++i) roots += find(static_cast<int>(i)) == static_cast<int>(i);
  return roots;
}

// Nearest face hit by a ray, and whether it was hit on its front side. At a
// tie (the ray through a shared edge) a front-side hit wins.
struct Hit {
  double t = std::numeric_limits<double>::infinity();
  bool front = false;
};

Hit cast_ray(const PolygonSoup& soup, const Vec3& origin, const Vec3& dir, double tie) {
  Hit best;
  for (const InputFace& f : soup.faces) {
    const std::vector<Vec3> p = face_points(soup, f);
    const Vec3 n = area_vector(p).normalized();
    const double denom = OpenMesh::dot(n, dir);
    if (std::abs(denom) < 1e-12) continue;
    const double t = OpenMesh::dot(n, p[0] - origin) / denom;
    if (t <= 0 || t > best.t + tie) continue;
    const Vec3 x = origin + t * dir;
    bool inside = true;
    for (std::size_t i = 0; i < p.size() && inside; ++i) {
      const Vec3 e = p[(i + 1) % p.size()] - p[i];
      inside = OpenMesh::dot(OpenMesh::cross(e, x - p[i]), n) >= -tie * e.norm();
    }
    if (!inside) continue;
    const bool front = denom < 0;
    if (t < best.t - tie) best = {t, front};
    else best.front = best.front || front;
    best.t = std::min(best.t, t);
  }
  return best;
}

// Equal to single precision: MTL numbers pass through tinyobjloader's own
// (not correctly rounded) parser.
bool close(const Rgb& a, const Rgb& b) {
  for (int k = 0; k < 3; ++k) {
    if (std::abs(a[k] - b[k]) > 1e-6 * std::max(1.0, std::abs(b[k]))) return false;
  }
  return true;
}

int emitter_groups(const PolygonSoup& soup) {
  std::set<int> groups;
  for (const InputFace& f : soup.faces) {
    if (soup.materials.at(f.material).is_emitter()) groups.insert(f.group);
  }
  return static_cast<int>(groups.size());
}

class GeneratedScenes : public ::testing::TestWithParam<std::string> {};

TEST_P(GeneratedScenes, IsDeterministic) {
  const PaperScene a = make_paper_scene(GetParam());
  const PaperScene b = make_paper_scene(GetParam());
  ASSERT_EQ(a.soup.points.size(), b.soup.points.size());
  ASSERT_EQ(a.soup.faces.size(), b.soup.faces.size());
  for (std::size_t i = 0; i < a.soup.points.size(); ++i) EXPECT_EQ(a.soup.points[i], b.soup.points[i]);
  for (std::size_t i = 0; i < a.soup.faces.size(); ++i) {
    EXPECT_EQ(a.soup.faces[i].vertices, b.soup.faces[i].vertices);
  }
}

TEST_P(GeneratedScenes, FacesAreValidPolygons) {
  const PaperScene s = make_paper_scene(GetParam());
  ASSERT_FALSE(s.soup.faces.empty());
  for (const Vec3& p : s.soup.points) {
    for (int k = 0; k < 3; ++k) ASSERT_TRUE(std::isfinite(p[k]));
  }
  for (const Material& m : s.soup.materials) {
    for (int k = 0; k < 3; ++k) {
      EXPECT_GE(m.reflectance[k], 0.0) << m.name;
      EXPECT_LT(m.reflectance[k], 1.0) << m.name;
      EXPECT_GE(m.emission[k], 0.0) << m.name;
    }
  }
  std::set<std::string> group_names(s.soup.groups.begin(), s.soup.groups.end());
  EXPECT_EQ(group_names.size(), s.soup.groups.size()) << "group names must be unique";
  for (const InputFace& f : s.soup.faces) {
    ASSERT_GE(f.material, 0);
    ASSERT_LT(f.material, static_cast<int>(s.soup.materials.size()));
    ASSERT_GE(f.group, 0);
    ASSERT_LT(f.group, static_cast<int>(s.soup.groups.size()));
    for (int v : f.vertices) {
      ASSERT_GE(v, 0);
      ASSERT_LT(v, static_cast<int>(s.soup.points.size()));
    }
    const std::vector<Vec3> p = face_points(s.soup, f);
    std::set<std::array<double, 3>> distinct;
    for (const Vec3& q : p) distinct.insert({q[0], q[1], q[2]});
    EXPECT_GE(distinct.size(), 3u) << s.soup.groups[f.group];
    const Vec3 a = area_vector(p);
    EXPECT_GT(a.norm(), 1e-6) << s.soup.groups[f.group];  // square metres
    // Planar: every vertex on the face's plane.
    const Vec3 n = a.normalized();
    for (const Vec3& q : p) EXPECT_NEAR(OpenMesh::dot(n, q - p[0]), 0.0, 1e-12);
  }
}

TEST_P(GeneratedScenes, HasEightDownwardLightsBelowTheCeiling) {
  const PaperScene s = make_paper_scene(GetParam());
  EXPECT_EQ(emitter_groups(s.soup), 8);
  for (const InputFace& f : s.soup.faces) {
    if (!s.soup.materials[f.material].is_emitter()) continue;
    const std::vector<Vec3> p = face_points(s.soup, f);
    const Vec3 n = area_vector(p).normalized();
    EXPECT_NEAR(n[1], -1.0, 1e-12);
    // Just below the ceiling: a ray going up from the light hits the
    // ceiling's front within a few centimetres.
    const Hit above = cast_ray(s.soup, centroid(p), Vec3(0, 1, 0), 1e-9);
    EXPECT_TRUE(above.front);
    EXPECT_GT(above.t, 0.0);
    EXPECT_LT(above.t, 0.05);
  }
}

// Room shells face their room, doorways and window recesses face into the
// opening, furniture boxes face outward (group names say which is which).
TEST_P(GeneratedScenes, FacesPointIntoOpenSpace) {
  const PaperScene s = make_paper_scene(GetParam());
  auto starts_with = [](const std::string& text, const std::string& prefix) { return text.rfind(prefix, 0) == 0; };
  auto contains = [](const std::string& text, const std::string& part) {
    return text.find(part) != std::string::npos;
  };
  std::map<int, int> faces_in_group;
  for (const InputFace& f : s.soup.faces) ++faces_in_group[f.group];
  int checked = 0;
  for (const InputFace& f : s.soup.faces) {
    const std::string& group = s.soup.groups[f.group];
    const std::vector<Vec3> p = face_points(s.soup, f);
    const Vec3 n = area_vector(p).normalized();
    const Vec3 c = centroid(p);
    const std::size_t shell = group.find("_floor") != std::string::npos     ? group.find("_floor")
                              : group.find("_ceiling") != std::string::npos ? group.find("_ceiling")
                                                                             : group.find("_wall_");
    if (contains(group, "_light")) continue;  // HasEightDownwardLightsBelowTheCeiling
    double side = 0;
    if (starts_with(group, "room") && shell != std::string::npos) {
      const std::string room = group.substr(0, shell);
      const Aabb floor = group_bounds(s.soup, room + "_floor");
      const Aabb ceiling = group_bounds(s.soup, room + "_ceiling");
      const Vec3 room_centre = 0.5 * (floor.lo + ceiling.hi);
      side = OpenMesh::dot(n, room_centre - c);
    } else if (starts_with(group, "door") || contains(group, "_window")) {
      side = OpenMesh::dot(n, group_centre(s.soup, f.group) - c);
    } else if (faces_in_group[f.group] > 1) {
      side = OpenMesh::dot(n, c - group_centre(s.soup, f.group));
    } else {
      continue;  // a lone visible face of a box; IsClosedAndEveryFaceSeesAFront covers it
    }
    EXPECT_GT(side, 0.0) << group;
    ++checked;
  }
  EXPECT_GT(checked, 300);
}

// The scenes are closed: a ray leaving a face along its normal always hits
// some face, and from at least one point of every face it hits a front side
// (points may be covered where furniture stands on or against the face).
TEST_P(GeneratedScenes, IsClosedAndEveryFaceSeesAFront) {
  const PaperScene s = make_paper_scene(GetParam());
  // Interior points off the faces' symmetry lines, so rays do not run along
  // the edges of aligned boxes.
  const std::vector<std::vector<double>> weights{
      {0.31, 0.23, 0.27, 0.19}, {0.61, 0.13, 0.07, 0.19}, {0.11, 0.57, 0.21, 0.11},
      {0.09, 0.17, 0.63, 0.11}, {0.13, 0.08, 0.17, 0.62}};
  for (const InputFace& f : s.soup.faces) {
    const std::vector<Vec3> p = face_points(s.soup, f);
    const Vec3 n = area_vector(p).normalized();
    int fronts = 0;
    for (const std::vector<double>& w : weights) {
      Vec3 origin(0, 0, 0);
      double total = 0;
      for (std::size_t i = 0; i < p.size(); ++i) {
        origin += w[i % w.size()] * p[i];
        total += w[i % w.size()];
      }
      origin /= total;
      const Hit hit = cast_ray(s.soup, origin + 1e-7 * n, n, 1e-9);
      EXPECT_TRUE(std::isfinite(hit.t)) << "ray from " << s.soup.groups[f.group] << " escapes";
      fronts += hit.front;
    }
    EXPECT_GT(fronts, 0) << s.soup.groups[f.group] << " faces into a solid";
  }
}

// Seats face what they are set at: the backrest is farther from it.
TEST(SceneGenerator, TwoRoomsSeatsFaceTheirTables) {
  const PaperScene s = make_paper_scene("two-rooms");
  const std::vector<std::array<std::string, 3>> seats{
      {"chair1_seat", "chair1_back", "dining_table_top"}, {"chair2_seat", "chair2_back", "dining_table_top"},
      {"chair3_seat", "chair3_back", "dining_table_top"}, {"chair4_seat", "chair4_back", "dining_table_top"},
      {"desk_chair_seat", "desk_chair_back", "desk_top"},  {"sofa_base", "sofa_back", "coffee_table_top"},
      {"armchair_base", "armchair_back", "coffee_table_top"}};
  for (const auto& [seat, back, table] : seats) {
    auto centre = [&](const std::string& g) {
      const Aabb b = group_bounds(s.soup, g);
      return Vec3(0.5 * (b.lo[0] + b.hi[0]), 0, 0.5 * (b.lo[2] + b.hi[2]));
    };
    const Vec3 t = centre(table);
    EXPECT_GT((centre(back) - t).norm(), (centre(seat) - t).norm()) << seat;
  }
}

TEST_P(GeneratedScenes, CameraIsInsideRoomOneLookingIntoIt) {
  const PaperScene s = make_paper_scene(GetParam());
  const Aabb floor = group_bounds(s.soup, "room1_floor");
  const Aabb ceiling = group_bounds(s.soup, "room1_ceiling");
  const Vec3& eye = s.camera.eye;
  EXPECT_GT(eye[0], floor.lo[0]);
  EXPECT_LT(eye[0], floor.hi[0]);
  EXPECT_GT(eye[2], floor.lo[2]);
  EXPECT_LT(eye[2], floor.hi[2]);
  EXPECT_GT(eye[1], floor.hi[1]);
  EXPECT_LT(eye[1], ceiling.lo[1]);
  EXPECT_GT((s.camera.target - eye).norm(), 0.1);
  EXPECT_GT(s.camera.fov_y_deg, 0.0);
  EXPECT_LT(s.camera.fov_y_deg, 180.0);
}

// docs/design.md §3 surfaces counted independently of split_into_surfaces.
TEST_P(GeneratedScenes, ReferenceSurfaceCountNearThePaper) {
  const PaperScene s = make_paper_scene(GetParam());
  const int paper = GetParam() == "two-rooms" ? kTwoRoomsPaperSurfaces : kFourRoomsPaperSurfaces;
  const int count = reference_surface_count(s.soup, kDefaultCreaseAngleDeg);
  EXPECT_NEAR(count, paper, 0.1 * paper);
}

// Depends on split_into_surfaces (mesh/surfaces.cpp).
TEST_P(GeneratedScenes, SplitIntoSurfacesMatchesReferenceAndPaper) {
  const PaperScene s = make_paper_scene(GetParam());
  const int paper = GetParam() == "two-rooms" ? kTwoRoomsPaperSurfaces : kFourRoomsPaperSurfaces;
  const SurfaceSplit split = split_into_surfaces(s.soup, kDefaultCreaseAngleDeg);
  const int count = static_cast<int>(split.surfaces.size());
  EXPECT_NEAR(count, paper, 0.1 * paper);
  EXPECT_EQ(count, reference_surface_count(s.soup, kDefaultCreaseAngleDeg));
  EXPECT_EQ(split.dropped_zero_area_faces, 0);
}

// Depends on load_scene and load_polygon_soup (io/scene_loader.cpp).
TEST_P(GeneratedScenes, WrittenFilesLoadBack) {
  const std::string name = GetParam();
  const PaperScene s = make_paper_scene(name);
  const std::filesystem::path dir = test::fresh_dir("scene_files_" + name);
  write_scene_files(s, dir, name);
  for (const char* ext : {".obj", ".mtl", ".scene.json"}) {
    EXPECT_TRUE(std::filesystem::is_regular_file(dir / (name + ext))) << ext;
  }
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir), std::filesystem::directory_iterator()), 3)
      << "no temporary files left behind";

  const PolygonSoup soup = load_polygon_soup(dir / (name + ".obj"));
  ASSERT_EQ(soup.faces.size(), s.soup.faces.size());
  for (std::size_t i = 0; i < soup.faces.size(); ++i) {
    const std::vector<Vec3> a = face_points(soup, soup.faces[i]);
    const std::vector<Vec3> b = face_points(s.soup, s.soup.faces[i]);
    ASSERT_EQ(a.size(), b.size()) << "face " << i;
    // The OBJ holds the shortest decimal that reads back to each double.
    for (std::size_t k = 0; k < a.size(); ++k) ASSERT_EQ(a[k], b[k]) << "face " << i;
    const Material& ma = soup.materials.at(soup.faces[i].material);
    const Material& mb = s.soup.materials.at(s.soup.faces[i].material);
    EXPECT_TRUE(close(ma.reflectance, mb.reflectance)) << mb.name;
    EXPECT_TRUE(close(ma.emission, mb.emission)) << mb.name;
    EXPECT_EQ(soup.groups.at(soup.faces[i].group), s.soup.groups.at(s.soup.faces[i].group));
  }

  const LoadResult loaded = load_scene(dir / (name + ".scene.json"));
  ASSERT_TRUE(loaded.scene.camera.has_value());
  EXPECT_EQ(loaded.scene.camera->eye, s.camera.eye);
  EXPECT_EQ(loaded.scene.camera->target, s.camera.target);
  EXPECT_EQ(loaded.scene.camera->up, s.camera.up);
  EXPECT_EQ(loaded.scene.camera->fov_y_deg, s.camera.fov_y_deg);
  EXPECT_EQ(loaded.scene.camera->width, s.camera.width);
  EXPECT_EQ(loaded.scene.camera->height, s.camera.height);
  EXPECT_EQ(static_cast<int>(loaded.scene.surfaces.size()), reference_surface_count(s.soup, kDefaultCreaseAngleDeg));
  int emitting_surfaces = 0;
  for (const Surface& surface : loaded.scene.surfaces) {
    emitting_surfaces += loaded.scene.materials.at(surface.material).is_emitter();
  }
  EXPECT_EQ(emitting_surfaces, 8);
}

INSTANTIATE_TEST_SUITE_P(PaperScenes, GeneratedScenes, ::testing::Values("two-rooms", "four-rooms"),
                         [](const ::testing::TestParamInfo<std::string>& info) {
                           return info.param == "two-rooms" ? std::string("TwoRooms") : std::string("FourRooms");
                         });

TEST(SceneGenerator, ListsBothScenesAndRejectsUnknownNames) {
  EXPECT_EQ(paper_scene_names(), (std::vector<std::string>{"two-rooms", "four-rooms"}));
  try {
    make_paper_scene("five-rooms");
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("five-rooms"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("two-rooms"), std::string::npos);
  }
}

TEST(SceneGenerator, MissingOutputDirectoryIsNamed) {
  const std::filesystem::path missing = test::fresh_dir("missing_parent") / "does-not-exist";
  try {
    write_scene_files(make_paper_scene("four-rooms"), missing, "four-rooms");
    FAIL() << "expected std::runtime_error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(missing.string()), std::string::npos) << e.what();
  }
  EXPECT_FALSE(std::filesystem::exists(missing));
}

// --- The bundled Cornell box (data/cornell) ---

std::filesystem::path cornell_dir() { return test::source_dir() / "data" / "cornell"; }

TEST(CornellBox, HasTheEightObjectsAndOneLight) {
  const PolygonSoup soup = load_polygon_soup(cornell_dir() / "cornell.obj");
  const std::set<std::string> groups(soup.groups.begin(), soup.groups.end());
  EXPECT_EQ(groups, (std::set<std::string>{"floor", "ceiling", "back_wall", "left_wall", "right_wall",
                                           "short_block", "tall_block", "light"}));
  std::map<std::string, int> faces_per_group;
  int emitters = 0;
  for (const InputFace& f : soup.faces) {
    ++faces_per_group[soup.groups.at(f.group)];
    emitters += soup.materials.at(f.material).is_emitter();
  }
  EXPECT_EQ(faces_per_group["short_block"], 5);
  EXPECT_EQ(faces_per_group["tall_block"], 5);
  EXPECT_EQ(faces_per_group["light"], 1);
  EXPECT_EQ(emitters, 1);
}

TEST(CornellBox, SpansThePublishedDimensions) {
  const PolygonSoup soup = load_polygon_soup(cornell_dir() / "cornell.obj");
  Vec3 lo(1e300, 1e300, 1e300);
  Vec3 hi(-1e300, -1e300, -1e300);
  for (const Vec3& p : soup.points) {
    lo.minimize(p);
    hi.maximize(p);
  }
  EXPECT_NEAR(hi[0] - lo[0], 556.0, 1e-9);
  EXPECT_NEAR(hi[1] - lo[1], 548.8, 1e-9);
  EXPECT_NEAR(hi[2] - lo[2], 559.2, 1e-9);
}

// Walls, floor, ceiling and light face the box centre; block faces face away
// from their block's centre, which is into the room as well.
TEST(CornellBox, EveryFaceFrontFacesTheRoom) {
  const PolygonSoup soup = load_polygon_soup(cornell_dir() / "cornell.obj");
  const Vec3 box_centre(278.0, 274.4, 279.6);
  for (const InputFace& f : soup.faces) {
    const std::string& group = soup.groups.at(f.group);
    const std::vector<Vec3> p = face_points(soup, f);
    const Vec3 n = area_vector(p).normalized();
    const Vec3 c = centroid(p);
    if (group == "short_block" || group == "tall_block") {
      EXPECT_GT(OpenMesh::dot(n, c - group_centre(soup, f.group)), 0.0) << group;
    } else {
      EXPECT_GT(OpenMesh::dot(n, box_centre - c), 0.0) << group;
    }
    // The published left wall is warped: its bottom edge slants, its top
    // edge does not. Every other polygon is planar.
    double off_plane = 0.0;
    for (const Vec3& q : p) off_plane = std::max(off_plane, std::abs(OpenMesh::dot(n, q - p[0])));
    if (group == "left_wall") {
      EXPECT_GT(off_plane, 1.0) << "the published left wall is warped";
    } else {
      EXPECT_NEAR(off_plane, 0.0, 1e-6) << group << " is not planar";
    }
  }
}

// As published, the light lies in the ceiling's plane (the loader puts it
// in front of the ceiling: test_bundled_data).
TEST(CornellBox, LightLiesInTheCeilingPlaneFacingDown) {
  const PolygonSoup soup = load_polygon_soup(cornell_dir() / "cornell.obj");
  for (const InputFace& f : soup.faces) {
    if (!soup.materials.at(f.material).is_emitter()) continue;
    const std::vector<Vec3> p = face_points(soup, f);
    const Vec3 a = area_vector(p);
    EXPECT_NEAR(a.normalized()[1], -1.0, 1e-12);
    EXPECT_NEAR(a.norm(), 130.0 * 105.0, 1e-6);
    for (const Vec3& q : p) EXPECT_NEAR(q[1], 548.8, 1e-9);
    const Material& m = soup.materials.at(f.material);
    EXPECT_EQ(m.emission, Rgb(17, 12, 4));
  }
}

// The published camera: 35 mm focal length on 25 mm film, so
// fov = 2 atan(12.5 / 35).
TEST(CornellBox, SceneFileHasThePublishedCamera) {
  const LoadResult loaded = load_scene(cornell_dir() / "cornell.scene.json");
  ASSERT_TRUE(loaded.scene.camera.has_value());
  const Camera& c = *loaded.scene.camera;
  EXPECT_EQ(c.eye, Vec3(278, 273, -800));
  EXPECT_EQ(c.target, Vec3(278, 273, 0));
  EXPECT_EQ(c.up, Vec3(0, 1, 0));
  EXPECT_NEAR(c.fov_y_deg, 2.0 * std::atan(12.5 / 35.0) * 180.0 / M_PI, 1e-4);
  EXPECT_EQ(c.width, 512);
  EXPECT_EQ(c.height, 512);
  // Five shell quads, five faces per block, one light: all distinct surfaces.
  EXPECT_EQ(loaded.scene.surfaces.size(), 16u);
}

}  // namespace
}  // namespace lhr
