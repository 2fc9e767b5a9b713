// Small parts seen past other objects (a table's aprons, legs, the top's
// underside) against the path tracer, an independent truth, in a lit room.
//
// Which links the shooter oracle keeps must not depend on what their own
// shadow rays found (docs/accuracy.md, "Judged by another draw"). Judged by
// its own draw, a partly hidden link whose rays found more of its shooter
// than is there was split and drawn afresh, and one whose rays found less
// was kept: the kept draws were low on average, and such parts came out a
// few per cent dark at their vertices, more with fewer rays.
//
// Between the vertices, the interpolant must hold a part's power: where a
// leg stands 1 cm proud of an apron, the apron's radiance bends down into
// the corner over a centimetre, and an element several centimetres wide
// cuts under it (docs/accuracy.md, "A surface's own power"). That must hold
// however many shooters share the light: the same room with its walls cut
// into tiles (docs/accuracy.md, "The sum of the graphs").

#include <gtest/gtest.h>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "mesh/initial_mesh.hpp"
#include "radiosity/linear_solver.hpp"
#include "radiosity/sampling.hpp"
#include "radiosity/tone_map.hpp"
#include "render/path_tracer.hpp"
#include "scene_fixtures.hpp"

namespace lhr {
namespace {

// A closed 4 x 2.7 x 4 room (ρ 0.6) lit by a square lamp under its ceiling,
// with a table (ρ 0.5) as furniture is built: a top with an overhang, four
// legs, and aprons set 1 cm behind the legs' faces. With tiles > 1 each of
// the room's six faces is cut into tiles x tiles squares, each a surface of
// its own: the same room, with 6 tiles² shooters instead of 6.
Scene room_with_a_table(int tiles = 1) {
  PolygonSoup soup;
  soup.materials = {test::grey_material("wall", 0.6), test::grey_material("wood", 0.5),
                    test::grey_material("lamp", 0.0, 20.0)};
  soup.groups = {"room", "top", "legs", "aprons", "lamp"};
  if (tiles == 1) {
    test::add_box(soup, Vec3(0, 0, 0), Vec3(4, 2.7, 4), true, 0, 0);
  } else {
    PolygonSoup room;
    test::add_box(room, Vec3(0, 0, 0), Vec3(4, 2.7, 4), true, 0, 0);
    for (const InputFace& face : room.faces) {
      const Vec3 a = room.points[face.vertices[0]], b = room.points[face.vertices[1]],
                 d = room.points[face.vertices[3]];
      const auto at = [&](int i, int j) { return a + (b - a) * (double(i) / tiles) + (d - a) * (double(j) / tiles); };
      for (int i = 0; i < tiles; ++i) {
        for (int j = 0; j < tiles; ++j) {
          soup.groups.push_back("tile" + std::to_string(soup.groups.size()));
          const int group = static_cast<int>(soup.groups.size()) - 1;
          test::add_quad(soup, at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1), 0, group);
        }
      }
    }
  }
  const double x0 = 1.2, x1 = 2.8, z0 = 1.5, z1 = 2.5, under = 0.71;
  test::add_box(soup, Vec3(x0, under, z0), Vec3(x1, 0.75, z1), false, 1, 1);
  for (const double lx : {x0 + 0.05, x1 - 0.11}) {
    for (const double lz : {z0 + 0.05, z1 - 0.11}) {
      test::add_box(soup, Vec3(lx, 0, lz), Vec3(lx + 0.06, under, lz + 0.06), false, 1, 2);
    }
  }
  test::add_box(soup, Vec3(x0 + 0.06, under - 0.08, z0 + 0.11), Vec3(x0 + 0.08, under, z1 - 0.11), false, 1, 3);
  test::add_box(soup, Vec3(x1 - 0.08, under - 0.08, z0 + 0.11), Vec3(x1 - 0.06, under, z1 - 0.11), false, 1, 3);
  test::add_box(soup, Vec3(x0 + 0.11, under - 0.08, z0 + 0.06), Vec3(x1 - 0.11, under, z0 + 0.08), false, 1, 3);
  test::add_box(soup, Vec3(x0 + 0.11, under - 0.08, z1 - 0.08), Vec3(x1 - 0.11, under, z1 - 0.06), false, 1, 3);
  // The lamp hangs 1 cm under the ceiling, off to one side of the table.
  test::add_quad(soup, Vec3(0.8, 2.69, 0.8), Vec3(1.3, 2.69, 0.8), Vec3(1.3, 2.69, 1.3), Vec3(0.8, 2.69, 1.3), 2, 4);
  return test::scene_from_soup(soup, "room with a table");
}

MeshingOptions default_meshing(const Scene& scene) {
  MeshingOptions meshing;
  meshing.max_edge = default_max_edge(scene);
  return meshing;
}

// A camera by the wall, looking at the table from the side.
LinearOptions looking_at_the_table(const MeshedScene& model) {
  LinearOptions options;
  options.view = test::view_from(model, Vec3(0.3, 1.0, 2.0), Vec3(1.2, 0.6, 2.0), Vec3(0, 1, 0), 50.0, 128, 96);
  return options;
}

TEST(SmallParts, VertexValuesAreThePathTracersWithFewRaysALink) {
  const Scene scene = room_with_a_table();
  MeshedScene model(scene, default_meshing(scene));
  LinearOptions options = looking_at_the_table(model);
  // Four rays a link: the fewer the rays, the larger the bias a selection
  // by the link's own draw makes.
  options.visibility_samples = 2;
  LinearSolver solver(model, options);
  solver.solve();

  const PathTracer tracer(scene);
  constexpr int kSamples = 256;
  // Per part of the table: Σ solver / Σ path tracer over its vertices (the
  // top's underside only, which sees the floor past the aprons and legs).
  struct Part {
    std::string group;
    double solved = 0.0, traced = 0.0;
    int vertices = 0;
  };
  std::vector<Part> parts{{"top", 0, 0, 0}, {"legs", 0, 0, 0}, {"aprons", 0, 0, 0}};
  std::uint64_t key = 0;
  for (int s = 0; s < model.num_surfaces(); ++s) {
    const Surface& surface = scene.surfaces[s];
    Part* part = nullptr;
    for (Part& p : parts) {
      if (surface.name.rfind(p.group, 0) == 0) part = &p;
    }
    if (!part || (part->group == "top" && surface.normal[1] > -0.99)) continue;
    Vec3 inside(0, 0, 0);
    for (const Vec3& p : surface.points) inside += p / static_cast<double>(surface.points.size());
    const SurfaceHierarchy& h = model.hierarchy(s);
    for (VertexId v = 0; v < static_cast<VertexId>(h.num_vertices()); ++v) {
      const std::optional<SurfaceStart> start = tracer.surface_start(h.point(v), surface.normal, inside);
      ASSERT_TRUE(start) << "vertex at " << h.point(v) << " of " << surface.name;
      // Contact lines (an apron's edge against the top's underside) are
      // judged in tests/test_contact_lines.cpp.
      if (tracer.enclosed_fraction(*start) > 0.01) continue;
      double traced = 0.0;
      for (int k = 0; k < kSamples; ++k) traced += luminance(tracer.sample_radiance(*start, ++key));
      part->traced += traced / kSamples;
      part->solved += luminance(solver.vertex_radiance(s)[v]);
      ++part->vertices;
    }
  }
  for (const Part& p : parts) {
    ASSERT_GT(p.vertices, 100) << p.group;
    // Judged by their own draws these read 0.911 (the top's underside),
    // 0.940 (legs) and 0.933 (aprons).
    EXPECT_NEAR(p.solved / p.traced, 1.0, 0.02) << p.group << ": " << p.vertices << " vertices";
  }
}

// The aprons' long faces (8 of them): ∫ L dA of the exported interpolant
// against the area times the path tracer's mean over uniform points (4000
// points, 16 paths each).
struct ApronFace {
  std::string name;
  double solved = 0.0, traced = 0.0;
};

std::vector<ApronFace> aprons_power(const Scene& scene, const MeshedScene& model, const LinearSolver& solver) {
  const PathTracer tracer(scene);
  constexpr int kPoints = 4000;
  std::vector<ApronFace> faces;
  for (int s = 0; s < model.num_surfaces(); ++s) {
    const Surface& surface = scene.surfaces[s];
    if (surface.name.rfind("aprons", 0) != 0 || surface.points.size() != 4) continue;
    const double area = model.surface_area(s);
    if (area < 0.04) continue;  // the top, bottom and ends
    ApronFace face{surface.name};
    const ConformingMesh mesh = model.hierarchy(s).conforming_mesh();
    const std::vector<Rgb> values = solver.vertex_radiance(s, mesh);
    for (const auto fh : mesh.mesh.faces()) {
      double mean = 0.0;
      for (const auto vh : mesh.mesh.fv_range(fh)) mean += luminance(values[vh.idx()]) / 3.0;
      face.solved += mean * mesh.mesh.calc_face_area(fh);
    }
    // A rectangle: p0 + u (p1 - p0) + v (p3 - p0).
    const std::vector<Vec3>& p = surface.points;
    Vec3 inside(0, 0, 0);
    for (const Vec3& q : p) inside += q / 4.0;
    for (int k = 0; k < kPoints; ++k) {
      const double u = unit_double(sample_key(s, k, 1)), v = unit_double(sample_key(s, k, 2));
      const Vec3 x = p[0] + u * (p[1] - p[0]) + v * (p[3] - p[0]);
      const std::optional<SurfaceStart> start = tracer.surface_start(x, surface.normal, inside);
      EXPECT_TRUE(start) << "point " << x << " of " << surface.name;
      if (!start) return {};
      for (int j = 0; j < 16; ++j) face.traced += luminance(tracer.sample_radiance(*start, sample_key(s, k, 3 + j)));
    }
    face.traced *= area / (16.0 * kPoints);
    faces.push_back(face);
  }
  return faces;
}

// The room (walls cut into tiles x tiles) solved with default rays and the
// aprons' faces measured; the eight together, solved over traced.
std::vector<ApronFace> aprons_in_a_solved_room(int tiles) {
  const Scene scene = room_with_a_table(tiles);
  MeshedScene model(scene, default_meshing(scene));
  LinearSolver solver(model, looking_at_the_table(model));
  solver.solve();
  return aprons_power(scene, model, solver);
}

double all_together(const std::vector<ApronFace>& faces) {
  double solved = 0.0, traced = 0.0;
  for (const ApronFace& face : faces) {
    solved += face.solved;
    traced += face.traced;
  }
  return solved / traced;
}

TEST(SmallParts, TheInterpolantHoldsEachApronsPower) {
  const std::vector<ApronFace> faces = aprons_in_a_solved_room(1);
  ASSERT_EQ(faces.size(), 8u);
  for (const ApronFace& face : faces) {
    // Refined only against the scene's power, four faces read 0.895–0.931
    // (the two under the table, which see its dark underside, among them);
    // now the worst reads 0.954.
    EXPECT_NEAR(face.solved / face.traced, 1.0, 0.07) << face.name;
  }
  // All eight: 0.942 refined only against the scene's power, 0.982 now.
  EXPECT_NEAR(all_together(faces), 1.0, 0.03);
}

// Cutting the room's walls into tiles changes nothing in the room, but each
// tile is a shooter of its own, and each graph now carries a small share of
// what the aprons receive. Judged graph by graph against the aprons' power,
// no one graph's bend into the corners beside the legs was enough to split
// there any more (docs/accuracy.md, "The sum of the graphs").
TEST(SmallParts, WallsCutIntoTilesLeaveTheApronsResolved) {
  const std::vector<ApronFace> faces = aprons_in_a_solved_room(4);
  ASSERT_EQ(faces.size(), 8u);
  // The bound the room with whole walls is held to. Judged graph by graph
  // the eight faces read 0.969 in all; the exported mesh's interpolant of
  // the path tracer's own values then missed 2.9 % of their power
  // (tools/midpoint-probe.py), 1.7 % judged by the sum.
  EXPECT_NEAR(all_together(faces), 1.0, 0.03);
}

}  // namespace
}  // namespace lhr
