// Invariant checks on conforming meshes (docs/design.md §3 output, §6 invariants),
// on hand-made meshes whose defects are known by construction, and through
// `lhr validate` on files.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "mesh/validate.hpp"
#include "test_support.hpp"

namespace lhr {
namespace {

std::vector<Violation> of_kind(const std::vector<Violation>& all, const std::string& kind) {
  std::vector<Violation> out;
  for (const Violation& v : all) {
    if (v.kind == kind) out.push_back(v);
  }
  return out;
}

std::string describe(const std::vector<Violation>& all) {
  std::string s;
  for (const Violation& v : all) s += format_violation(v) + "\n";
  return s;
}

// Unit square A B C D, counter-clockwise seen from +z.
RawMesh square() {
  RawMesh m;
  m.points = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  m.faces = {{0, 1, 2}, {0, 2, 3}};
  return m;
}

// Closed tetrahedron, every face counter-clockwise seen from outside.
RawMesh tetrahedron() {
  RawMesh m;
  m.points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  m.faces = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  return m;
}

// The square cut along A-C: one triangle A C D on the left, and on the right
// A B M, B C M with M the midpoint of A-C, so M lies inside the left
// triangle's edge A-C: the classic crack of an unclosed T-vertex.
RawMesh t_junction_square() {
  RawMesh m;
  m.points = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0.5, 0.5, 0}};
  m.faces = {{0, 2, 3}, {0, 1, 4}, {1, 2, 4}};
  return m;
}

// Regular n x n grid of unit squares, two triangles each, consistently oriented.
RawMesh grid(int n) {
  RawMesh m;
  for (int j = 0; j <= n; ++j) {
    for (int i = 0; i <= n; ++i) m.points.emplace_back(i, j, 0.0);
  }
  auto id = [n](int i, int j) { return j * (n + 1) + i; };
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      m.faces.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      m.faces.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  }
  return m;
}

TEST(CheckConformingMesh, CleanSquarePasses) {
  const auto v = check_conforming_mesh(square());
  EXPECT_TRUE(v.empty()) << describe(v);
}

TEST(CheckConformingMesh, ClosedTetrahedronAndQuadPass) {
  auto v = check_conforming_mesh(tetrahedron());
  EXPECT_TRUE(v.empty()) << describe(v);
  RawMesh quad = square();
  quad.faces = {{0, 1, 2, 3}};
  v = check_conforming_mesh(quad);
  EXPECT_TRUE(v.empty()) << describe(v);
}

TEST(CheckConformingMesh, TJunctionCrackIsRejected) {
  const auto v = check_conforming_mesh(t_junction_square());
  const auto t = of_kind(v, "t-junction");
  ASSERT_EQ(t.size(), 1u) << describe(v);
  EXPECT_EQ(t[0].where, "vertex 4");
  EXPECT_NE(t[0].detail.find("edge (0,2)"), std::string::npos) << t[0].detail;
  EXPECT_EQ(v.size(), 1u) << "the crack is the only defect:\n" << describe(v);
}

TEST(CheckConformingMesh, TJunctionFoundAtAnyScale) {
  for (double scale : {1e-6, 1.0, 1e6}) {
    RawMesh m = t_junction_square();
    for (Vec3& p : m.points) p = p * scale + Vec3(3.0 * scale, -7.0 * scale, 11.0 * scale);
    EXPECT_EQ(of_kind(check_conforming_mesh(m), "t-junction").size(), 1u) << "scale " << scale;
  }
}

TEST(CheckConformingMesh, VertexOffTheEdgeBeyondToleranceIsNoTJunction) {
  RawMesh m = t_junction_square();
  m.points[4][2] = 1e-3;  // lifted: a gap, but the vertex does not lie on A-C
  EXPECT_TRUE(of_kind(check_conforming_mesh(m), "t-junction").empty());
  // A looser tolerance takes it as lying on the edge again.
  ConformingCheckOptions loose;
  loose.relative_tolerance = 1e-2;
  EXPECT_EQ(of_kind(check_conforming_mesh(m, loose), "t-junction").size(), 1u);
}

TEST(CheckConformingMesh, TouchingComponentsAreAccepted) {
  // Same geometry as the crack, but the left triangle has its own copies of
  // A and C: two surfaces meeting, which docs/design.md §3 allows.
  RawMesh m = t_junction_square();
  m.points.push_back(m.points[0]);
  m.points.push_back(m.points[2]);
  m.faces[0] = {5, 6, 3};
  const auto v = check_conforming_mesh(m);
  EXPECT_TRUE(v.empty()) << describe(v);
}

TEST(CheckConformingMesh, FlippedFaceOfClosedTetrahedronIsRejected) {
  RawMesh m = tetrahedron();
  std::swap(m.faces[3][1], m.faces[3][2]);
  const auto v = check_conforming_mesh(m);
  // Each of the flipped face's three edges is walked the same way twice.
  const auto o = of_kind(v, "orientation");
  EXPECT_EQ(o.size(), 3u) << describe(v);
  EXPECT_EQ(v.size(), o.size()) << describe(v);
  std::vector<std::string> where;
  for (const Violation& x : o) where.push_back(x.where);
  std::sort(where.begin(), where.end());
  EXPECT_EQ(where, (std::vector<std::string>{"edge (1,2)", "edge (1,3)", "edge (2,3)"}));
}

TEST(CheckConformingMesh, EdgeOfThreeFacesIsNonManifold) {
  RawMesh m;
  m.points = {{0, 0, 0}, {1, 0, 0}, {0.5, 1, 0}, {0.5, -1, 0}, {0.5, 0, 1}};
  m.faces = {{0, 1, 2}, {1, 0, 3}, {1, 0, 4}};
  const auto v = check_conforming_mesh(m);
  const auto e = of_kind(v, "non-manifold-edge");
  ASSERT_EQ(e.size(), 1u) << describe(v);
  EXPECT_EQ(e[0].where, "edge (0,1)");
}

TEST(CheckConformingMesh, DuplicatedFaceIsRejected) {
  RawMesh m = square();
  m.faces.push_back({2, 1, 0});  // same vertex set as face 0, either winding
  const auto v = check_conforming_mesh(m);
  const auto d = of_kind(v, "duplicate-face");
  ASSERT_EQ(d.size(), 1u) << describe(v);
  EXPECT_EQ(d[0].where, "face 2");
  EXPECT_NE(d[0].detail.find("face 0"), std::string::npos);
}

TEST(CheckConformingMesh, DegenerateFacesAreRejectedAndThinOnesAreNot) {
  RawMesh m = square();
  m.points.push_back({2, 0, 0});
  m.points.push_back({3, 0, 0});
  m.faces.push_back({1, 4, 5});  // three collinear points: zero area
  auto v = check_conforming_mesh(m);
  auto d = of_kind(v, "degenerate-face");
  ASSERT_EQ(d.size(), 1u) << describe(v);
  EXPECT_EQ(d[0].where, "face 2");

  // Heights against the 3.16 bounding-box diagonal: 1e-12 is below the
  // default 1e-9 relative tolerance, 1e-6 is a thin but honest sliver.
  m.points[4] = {2, 1e-12, 0};
  EXPECT_EQ(of_kind(check_conforming_mesh(m), "degenerate-face").size(), 1u);
  m.points[4] = {2, 1e-6, 0};
  v = check_conforming_mesh(m);
  EXPECT_TRUE(of_kind(v, "degenerate-face").empty()) << describe(v);
}

TEST(CheckConformingMesh, NonFiniteCoordinateIsRejected) {
  RawMesh m = square();
  m.points[2][1] = std::numeric_limits<double>::quiet_NaN();
  auto v = of_kind(check_conforming_mesh(m), "non-finite-coordinate");
  ASSERT_EQ(v.size(), 1u);
  EXPECT_EQ(v[0].where, "vertex 2");
  m.points[2][1] = std::numeric_limits<double>::infinity();
  EXPECT_EQ(of_kind(check_conforming_mesh(m), "non-finite-coordinate").size(), 1u);
}

TEST(CheckConformingMesh, RadianceMustBeFiniteAndNonNegative) {
  RawMesh m = square();
  m.radiance = {{0, 0, 0}, {1, 2, 3}, {0.5, -1e-3, 0}, {std::nan(""), 0, 0}};
  const auto v = check_conforming_mesh(m);
  const auto neg = of_kind(v, "negative-radiance");
  const auto nan = of_kind(v, "non-finite-radiance");
  ASSERT_EQ(neg.size(), 1u) << describe(v);
  ASSERT_EQ(nan.size(), 1u) << describe(v);
  EXPECT_EQ(neg[0].where, "vertex 2");
  EXPECT_EQ(nan[0].where, "vertex 3");
  m.radiance.pop_back();
  EXPECT_EQ(of_kind(check_conforming_mesh(m), "radiance-count").size(), 1u);
}

TEST(CheckConformingMesh, BadIndicesAndShortFacesAreRejected) {
  RawMesh m = square();
  m.faces.push_back({0, 1, 4});   // 4 is out of range
  m.faces.push_back({0, 1, -1});  // so is -1
  m.faces.push_back({0, 1});      // too few vertices
  m.faces.push_back({0, 1, 1});   // repeated vertex
  const auto v = check_conforming_mesh(m);
  EXPECT_EQ(of_kind(v, "index-out-of-range").size(), 2u) << describe(v);
  EXPECT_EQ(of_kind(v, "face-size").size(), 1u) << describe(v);
  const auto r = of_kind(v, "repeated-vertex");
  ASSERT_EQ(r.size(), 1u) << describe(v);
  EXPECT_EQ(r[0].where, "face 5");
}

TEST(CheckConformingMesh, BowtieVertexIsNonManifold) {
  RawMesh m;
  m.points = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {-1, 0, 0}, {-1, -1, 0}};
  m.faces = {{0, 1, 2}, {0, 3, 4}};  // two triangles that share vertex 0 only
  const auto v = check_conforming_mesh(m);
  const auto n = of_kind(v, "non-manifold-vertex");
  ASSERT_EQ(n.size(), 1u) << describe(v);
  EXPECT_EQ(n[0].where, "vertex 0");
  EXPECT_EQ(v.size(), 1u) << describe(v);
}

TEST(CheckConformingMesh, LargeGridWithOneCrack) {
  constexpr int kN = 150;  // 45,000 triangles
  RawMesh m = grid(kN);
  auto v = check_conforming_mesh(m);
  EXPECT_TRUE(v.empty()) << describe(v);

  // Split one triangle's hypotenuse neighbour: cell (i,j) upper-left triangle
  // becomes two through the midpoint of the shared diagonal, while the
  // lower-right triangle keeps the whole diagonal: one T-junction.
  const int i = 70, j = 33;
  auto id = [](int a, int b) { return b * (kN + 1) + a; };
  const int mid = static_cast<int>(m.points.size());
  m.points.emplace_back(i + 0.5, j + 0.5, 0.0);
  const std::size_t upper = 2 * (static_cast<std::size_t>(j) * kN + i) + 1;
  m.faces[upper] = {id(i, j), mid, id(i, j + 1)};
  m.faces.push_back({mid, id(i + 1, j + 1), id(i, j + 1)});
  v = check_conforming_mesh(m);
  const auto t = of_kind(v, "t-junction");
  ASSERT_EQ(t.size(), 1u) << describe(v);
  EXPECT_EQ(t[0].where, "vertex " + std::to_string(mid));
  EXPECT_EQ(v.size(), 1u) << describe(v);
}

TEST(CheckConformingMesh, ReportIsCappedPerKindWithACount) {
  RawMesh m;
  for (int k = 0; k < 100; ++k) {
    m.points.emplace_back(k, 0, 0);
    m.points.emplace_back(k, 1, 0);
    m.faces.push_back({2 * k, 2 * k + 1, 2 * k + 1});  // repeated vertex
  }
  const auto v = check_conforming_mesh(m);
  const auto r = of_kind(v, "repeated-vertex");
  ASSERT_EQ(r.size(), 21u);
  EXPECT_NE(r.back().detail.find("80 more"), std::string::npos) << r.back().detail;
  EXPECT_NE(r.back().detail.find("100 in total"), std::string::npos) << r.back().detail;
}

TEST(FormatViolation, KindWhereDetail) {
  EXPECT_EQ(format_violation({"t-junction", "vertex 4", "lies inside edge (0,2)"}),
            "t-junction at vertex 4: lies inside edge (0,2)");
}

// ---------------------------------------------------------------------------
// `lhr validate` on files.

// Vertex and face lines shared by the OFF and ASCII PLY bodies.
std::string text_body(const RawMesh& m) {
  std::ostringstream out;
  out.precision(17);
  for (const Vec3& p : m.points) out << p[0] << ' ' << p[1] << ' ' << p[2] << '\n';
  for (const auto& f : m.faces) {
    out << f.size();
    for (int v : f) out << ' ' << v;
    out << '\n';
  }
  return out.str();
}

std::string off_text(const RawMesh& m) {
  std::ostringstream out;
  out << "OFF\n" << m.points.size() << ' ' << m.faces.size() << " 0\n" << text_body(m);
  return out.str();
}

std::string ply_header(const RawMesh& m, const char* format) {
  std::ostringstream out;
  out << "ply\nformat " << format << " 1.0\nelement vertex " << m.points.size()
      << "\nproperty float x\nproperty float y\nproperty float z\nelement face " << m.faces.size()
      << "\nproperty list uchar int vertex_indices\nend_header\n";
  return out.str();
}

std::string ply_text(const RawMesh& m) { return ply_header(m, "ascii") + text_body(m); }

// Binary PLY written byte by byte, so a NaN survives (text readers cannot parse one).
std::string binary_ply(const RawMesh& m) {
  std::string s = ply_header(m, "binary_little_endian");
  auto put = [&s](const auto& value) {
    char bytes[sizeof value];
    std::memcpy(bytes, &value, sizeof value);
    s.append(bytes, sizeof value);
  };
  for (const Vec3& p : m.points) {
    for (int c = 0; c < 3; ++c) put(static_cast<float>(p[c]));
  }
  for (const auto& f : m.faces) {
    put(static_cast<std::uint8_t>(f.size()));
    for (int v : f) put(static_cast<std::int32_t>(v));
  }
  return s;
}

TEST(ValidateCommand, GoodMeshesExitZero) {
  const auto dir = test::fresh_dir("validate_good");
  test::write_text(dir / "square.off", off_text(square()));
  test::write_text(dir / "tetra.ply", ply_text(tetrahedron()));
  RawMesh touching = t_junction_square();
  touching.points.push_back(touching.points[0]);
  touching.points.push_back(touching.points[2]);
  touching.faces[0] = {5, 6, 3};
  test::write_text(dir / "touching.ply", binary_ply(touching));
  for (const char* name : {"square.off", "tetra.ply", "touching.ply"}) {
    const auto r = test::run_lhr({"validate", (dir / name).string()});
    EXPECT_EQ(r.exit_code, 0) << name << "\n" << r.out << r.err;
    EXPECT_NE(r.out.find("ok"), std::string::npos) << r.out;
    EXPECT_TRUE(r.err.empty()) << r.err;
  }
}

TEST(ValidateCommand, BadMeshesExitOneNamingTheKind) {
  const auto dir = test::fresh_dir("validate_bad");
  RawMesh flipped = tetrahedron();
  std::swap(flipped.faces[0][1], flipped.faces[0][2]);
  RawMesh nan = square();
  nan.points[1][0] = std::numeric_limits<double>::quiet_NaN();
  RawMesh three = square();
  three.points.push_back({0.5, 0.5, 1});
  three.faces.push_back({0, 2, 4});
  struct Case {
    std::string file;
    std::string text;
    std::string kind;
  };
  const std::vector<Case> cases = {
      {"crack.off", off_text(t_junction_square()), "t-junction"},
      {"crack.ply", binary_ply(t_junction_square()), "t-junction"},
      {"flipped.ply", ply_text(flipped), "orientation"},
      {"nan.ply", binary_ply(nan), "non-finite-coordinate"},
      {"fin.off", off_text(three), "non-manifold-edge"},
  };
  for (const Case& c : cases) {
    test::write_text(dir / c.file, c.text);
    const auto r = test::run_lhr({"validate", (dir / c.file).string()});
    EXPECT_EQ(r.exit_code, 1) << c.file << "\n" << r.out << r.err;
    EXPECT_NE(r.out.find(c.kind + " at "), std::string::npos) << c.file << "\n" << r.out;
  }
}

TEST(ValidateCommand, CrackSurvivesFloatStorage) {
  // Corners no float holds exactly: the midpoint read back lies ~1e-8 off
  // the stored edge, and must still count as on it.
  RawMesh m;
  const Vec3 a(0.1, 0.3, 0.7), b(1.3, 0.2, 0.9), c(1.7, 1.9, 0.3), d(0.2, 1.1, 0.55);
  m.points = {a, b, c, d, (a + c) * 0.5};
  m.faces = {{0, 2, 3}, {0, 1, 4}, {1, 2, 4}};
  const auto dir = test::fresh_dir("validate_float");
  test::write_text(dir / "crack.ply", binary_ply(m));
  const auto r = test::run_lhr({"validate", (dir / "crack.ply").string()});
  EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
  EXPECT_NE(r.out.find("t-junction at vertex 4"), std::string::npos) << r.out;
}

TEST(ValidateCommand, MissingOrUnreadableFileIsOneLineOnStderr) {
  const auto dir = test::fresh_dir("validate_missing");
  test::write_text(dir / "garbage.ply", "this is not a mesh\n\x01\x02\x03");
  test::write_text(dir / "empty.off", "");
  for (const char* name : {"nope.ply", "garbage.ply", "empty.off"}) {
    const auto file = (dir / name).string();
    const auto r = test::run_lhr({"validate", file});
    EXPECT_EQ(r.exit_code, 1) << name << "\n" << r.out << r.err;
    EXPECT_EQ(test::count_lines(r.err), 1) << r.err;
    EXPECT_NE(r.err.find(file), std::string::npos) << r.err;
  }
}

}  // namespace
}  // namespace lhr
