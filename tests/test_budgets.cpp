// Budgets (issue 6 item 4, docs/robustness.md): --max-links and --max-memory
// stop refinement with a warning, the solution stays valid (a restricted
// quadtree, finite non-negative values, the same whatever the thread
// count), and the process's peak memory stays within the stated margin.

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "io/scene_loader.hpp"
#include "mesh/hierarchy.hpp"
#include "mesh/hierarchy_check.hpp"
#include "mesh/initial_mesh.hpp"
#include "mesh/validate.hpp"
#include "radiosity/classical_solver.hpp"
#include "radiosity/interaction_graph.hpp"
#include "radiosity/linear_solver.hpp"
#include "radiosity/memory_budget.hpp"
#include "scene_fixtures.hpp"
#include "test_support.hpp"

namespace lhr {
namespace {

const Scene& cornell() {
  static const LoadResult loaded = load_scene(test::source_dir() / "data/cornell/cornell.scene.json");
  return loaded.scene;
}

MeshingOptions coarse_meshing() {
  MeshingOptions meshing;
  meshing.max_edge = 120.0;
  return meshing;
}

struct Outcome {
  std::size_t links = 0;
  std::size_t bytes = 0;
  bool link_budget = false, memory_budget = false;
  std::size_t linked_past_budget = 0;  // linear: first links of late shooters
  std::vector<Rgb> values;  // every surface's vertex radiance, in order
};

template <class Stats>
Outcome outcome_of(const Stats& stats) {
  Outcome o;
  o.links = stats.links;
  o.bytes = stats.bytes_total();
  o.link_budget = stats.link_budget_reached;
  o.memory_budget = stats.memory_budget_reached;
  return o;
}

void expect_valid(const MeshedScene& model, const Outcome& o) {
  for (int s = 0; s < model.num_surfaces(); ++s) {
    for (const Violation& v : check_hierarchy(model.hierarchy(s))) ADD_FAILURE() << format_violation(v);
  }
  for (const Rgb& value : o.values) {
    for (int c = 0; c < 3; ++c) ASSERT_TRUE(std::isfinite(value[c]) && value[c] >= 0);
  }
}

Outcome solve_linear(std::size_t max_links, std::size_t max_bytes, int threads = 0) {
  std::optional<tbb::global_control> limit;
  if (threads > 0) limit.emplace(tbb::global_control::max_allowed_parallelism, threads);
  MeshedScene model(cornell(), coarse_meshing());
  LinearOptions options = test::quick_linear_options(model, 5.0, 0.1, 128);
  options.max_links = max_links;
  options.max_bytes = max_bytes;
  LinearSolver solver(model, options);
  solver.solve();
  Outcome o = outcome_of(solver.stats());
  o.linked_past_budget = solver.stats().links_linked_past_budget;
  for (int s = 0; s < model.num_surfaces(); ++s) {
    const auto& v = solver.vertex_radiance(s);
    o.values.insert(o.values.end(), v.begin(), v.end());
  }
  expect_valid(model, o);
  return o;
}

Outcome solve_classical(std::size_t max_links, std::size_t max_bytes) {
  MeshedScene model(cornell(), coarse_meshing());
  ClassicalOptions options;
  options.eps_bf = 1e-3;
  options.visibility_samples = 2;
  options.max_links = max_links;
  options.max_bytes = max_bytes;
  ClassicalSolver solver(model, options);
  solver.solve();
  Outcome o = outcome_of(solver.stats());
  for (int s = 0; s < model.num_surfaces(); ++s) {
    const SurfaceHierarchy& h = model.hierarchy(s);
    for (NodeId n : h.leaves()) o.values.push_back(solver.radiance(s, n));
  }
  expect_valid(model, o);
  return o;
}

// A refinement step that starts below the link budget finishes: one
// receiver split seeds links at its new vertices (paper §3: 9 per split),
// one shooter refinement adds 3. Its links beyond the budget are bounded.
constexpr std::size_t kLinkOvershoot = 64;

TEST(Budgets, LinearStopsAtMaxLinksAndStaysValid) {
  const Outcome free = solve_linear(0, 0);
  EXPECT_FALSE(free.link_budget || free.memory_budget);
  const std::size_t budget = free.links / 3;
  const Outcome capped = solve_linear(budget, 0);
  EXPECT_TRUE(capped.link_budget);
  EXPECT_FALSE(capped.memory_budget);
  EXPECT_LE(capped.links, budget + kLinkOvershoot + capped.linked_past_budget);
  // Late shooters' root links are few: the budget is not a formality.
  // Measured: 5 004 of them under a cap of 113 928 (a third of the free
  // run's 341 784 links), about 5 000 for a cap anywhere from a quarter to
  // half of it: the dim surfaces that start shooting once the cap is
  // reached. (Before links were coarsened the free run made 2.0 M links and
  // a third of that was reached later, past 1 570 such links.)
  EXPECT_LT(capped.linked_past_budget, budget / 20);
  EXPECT_GT(capped.links, budget / 2) << "refinement stopped long before the budget";
}

TEST(Budgets, LinearStopsBeforeMaxBytesTheSameWhateverTheThreadCount) {
  const Outcome free = solve_linear(0, 0);
  const std::size_t budget = free.bytes / 3;
  const Outcome one = solve_linear(0, budget, 1), two = solve_linear(0, budget, 2);
  EXPECT_TRUE(one.memory_budget);
  EXPECT_FALSE(one.link_budget);
  EXPECT_LE(one.bytes, budget);
  EXPECT_GT(one.bytes, budget / 3) << "refinement stopped long before the budget";
  EXPECT_EQ(one.links, two.links);
  ASSERT_EQ(one.values.size(), two.values.size());
  for (std::size_t i = 0; i < one.values.size(); ++i) {
    for (int c = 0; c < 3; ++c) ASSERT_EQ(one.values[i][c], two.values[i][c]) << "vertex " << i;
  }
}

TEST(Budgets, ClassicalStopsAtEitherBudgetAndStaysValid) {
  const Outcome free = solve_classical(0, 0);
  EXPECT_FALSE(free.link_budget || free.memory_budget);
  const Outcome by_links = solve_classical(free.links / 3, 0);
  EXPECT_TRUE(by_links.link_budget);
  // A receiver split hands all its links to four children at once, and so
  // does a leaf split as a shooter; both are counted before they are made
  // (measured here: 753 past the budget).
  EXPECT_LE(by_links.links, free.links / 3 + 16 * kLinkOvershoot);
  const Outcome by_bytes = solve_classical(0, free.bytes / 3);
  EXPECT_TRUE(by_bytes.memory_budget);
  EXPECT_LE(by_bytes.bytes, free.bytes / 3);
  EXPECT_LT(by_bytes.links, free.links);
}

// Peak resident memory of `lhr solve` (its stats.json, getrusage) against
// the budget. The stated margin (docs/robustness.md): the peak stays within
// the base — the same solve stopped after linking (--max-links 1): scene,
// initial meshes, ray-tracing structure, libraries, image — plus 1.2 times
// the budget. Under AddressSanitizer memory is shadowed and quarantined, so
// resident sizes say nothing there.
constexpr bool kResidentSizesMeaningful = !test::kUnderAddressSanitizer;

nlohmann::json solve_file(const std::filesystem::path& scene, const std::string& name,
                          const std::vector<std::string>& flags, std::string* err) {
  const auto dir = test::fresh_dir(name);
  std::vector<std::string> args = {"solve", scene.string(), "--out", dir.string()};
  args.insert(args.end(), flags.begin(), flags.end());
  const auto r = test::run_lhr(args);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  if (err) *err = r.err;
  return nlohmann::json::parse(test::read_text(dir / "stats.json"));
}

nlohmann::json solve_cornell(const std::string& name, const std::vector<std::string>& flags, std::string* err) {
  return solve_file(test::source_dir() / "data/cornell/cornell.scene.json", name, flags, err);
}


// The margin the issue asks of the default budget: 1.2 times the budget over
// the base (docs/robustness.md states it).
constexpr double kPeakMargin = 1.2;

// The capped run stopped at its budget, its counted data within it, and its
// peak within the margin over the base run's.
void expect_peak_within_margin(const nlohmann::json& base, const nlohmann::json& capped, double budget_mib) {
  constexpr double kMiB = 1024.0 * 1024.0;
  EXPECT_TRUE(capped["memory_budget_reached"].get<bool>());
  EXPECT_LE(capped["bytes"]["total"].get<double>(), budget_mib * kMiB);
  const double base_mib = base["peak_memory_mib"].get<double>();
  const double peak_mib = capped["peak_memory_mib"].get<double>();
  ::testing::Test::RecordProperty("base_mib", std::to_string(base_mib));
  ::testing::Test::RecordProperty("peak_mib", std::to_string(peak_mib));
  EXPECT_LE(peak_mib, base_mib + kPeakMargin * budget_mib) << "base " << base_mib << " MiB";
}

TEST(Budgets, PeakMemoryStaysWithinTheMemoryBudgetPlusMargin) {
  if (!kResidentSizesMeaningful) GTEST_SKIP() << "resident sizes are meaningless under AddressSanitizer";
  const nlohmann::json base = solve_cornell("budget_base", {"--max-links", "1"}, nullptr);
  std::string err;
  const nlohmann::json capped = solve_cornell("budget_memory", {"--max-memory", "24M"}, &err);
  EXPECT_NE(err.find("warning: --max-memory reached"), std::string::npos) << err;
  expect_peak_within_margin(base, capped, 24);
}

TEST(Budgets, ClassicalPeakMemoryOnAGlowingCubeStaysWithinTheBudgetPlusMargin) {
  // Each refinement pass once listed every new link before its coefficients
  // (at more bytes than a finished link), uncounted: 1.5 times the budget
  // over the base at 24 MiB, 2 times at 100 MiB.
  if (!kResidentSizesMeaningful) GTEST_SKIP() << "resident sizes are meaningless under AddressSanitizer";
  const auto dir = test::fresh_dir("budget_cube");
  test::write_glowing_cube(dir);
  const nlohmann::json base =
      solve_file(dir / "cube.obj", "budget_cube_base", {"--method", "classical", "--max-links", "1"}, nullptr);
  const nlohmann::json capped =
      solve_file(dir / "cube.obj", "budget_cube_capped", {"--method", "classical", "--max-memory", "16M"}, nullptr);
  expect_peak_within_margin(base, capped, 16);
}

// A floor with a 20 × 20 field of boxes of five heights and a lamp above
// (docs/robustness.md, "Budgets"): 2 002 surfaces, so the pairs of surfaces
// run to millions. `boxes` false leaves only the floor and the lamp.
void write_box_field(const std::filesystem::path& dir, bool boxes) {
  std::ostringstream v, f;
  int n = 0;
  const auto quad = [&](const std::array<Vec3, 4>& q, const char* material) {
    for (const Vec3& p : q) v << "v " << p[0] << ' ' << p[1] << ' ' << p[2] << '\n';
    f << "usemtl " << material << "\nf " << n + 1 << ' ' << n + 2 << ' ' << n + 3 << ' ' << n + 4 << '\n';
    n += 4;
  };
  quad({Vec3(-1, 0, -1), Vec3(-1, 0, 21), Vec3(21, 0, 21), Vec3(21, 0, -1)}, "floor");
  for (int i = 0; boxes && i < 20; ++i) {
    for (int j = 0; j < 20; ++j) {
      const double x0 = i + 0.25, z0 = j + 0.25, x1 = x0 + 0.5, z1 = z0 + 0.5, h = 0.5 + ((i * 7 + j * 3) % 5) * 0.3;
      f << "g box" << i << '_' << j << '\n';
      quad({Vec3(x0, h, z0), Vec3(x0, h, z1), Vec3(x1, h, z1), Vec3(x1, h, z0)}, "box");
      quad({Vec3(x0, 0, z0), Vec3(x0, h, z0), Vec3(x1, h, z0), Vec3(x1, 0, z0)}, "box");
      quad({Vec3(x1, 0, z1), Vec3(x1, h, z1), Vec3(x0, h, z1), Vec3(x0, 0, z1)}, "box");
      quad({Vec3(x0, 0, z1), Vec3(x0, h, z1), Vec3(x0, h, z0), Vec3(x0, 0, z0)}, "box");
      quad({Vec3(x1, 0, z0), Vec3(x1, h, z0), Vec3(x1, h, z1), Vec3(x1, 0, z1)}, "box");
    }
  }
  f << "g lamp\n";
  quad({Vec3(9, 6, 9), Vec3(11, 6, 9), Vec3(11, 6, 11), Vec3(9, 6, 11)}, "lamp");
  std::ofstream(dir / "boxes.obj") << "mtllib boxes.mtl\n" << v.str() << f.str();
  std::ofstream(dir / "boxes.mtl") << "newmtl floor\nKd 0.6 0.6 0.6\nnewmtl box\nKd 0.7 0.7 0.7\n"
                                      "newmtl lamp\nKd 0 0 0\nKe 20 20 20\n";
}

// Making the first links needs little memory beside what they leave: at
// most the budget's margin over the data, both methods. Made all at once,
// the pairs' working lists came to 80 MiB beside the classical method's
// 18 MiB of data (a list of 24 bytes a pair), and the linear method's
// graphs of pairs that exchange nothing to 1.4 times its data, before any
// was dropped. The process's own footprint is that of the same floor and
// lamp without the boxes.
TEST(Budgets, FirstLinksAmongManySurfacesNeedLittleMemoryBesideTheirData) {
  if (!kResidentSizesMeaningful) GTEST_SKIP() << "resident sizes are meaningless under AddressSanitizer";
  constexpr double kMiB = 1024.0 * 1024.0;
  const auto field = test::fresh_dir("budget_box_field");
  write_box_field(field, true);
  const auto bare = test::fresh_dir("budget_bare_floor");
  write_box_field(bare, false);
  for (const std::string method : {"classical", "linear"}) {
    SCOPED_TRACE(method);
    // Linked by the third iteration: the lamp, then every surface it lit.
    const std::vector<std::string> flags = {"--method", method, "--max-links", "1", "--max-iterations", "3"};
    const nlohmann::json floor = solve_file(bare / "boxes.obj", "budget_bare_floor_out", flags, nullptr);
    const nlohmann::json boxes = solve_file(field / "boxes.obj", "budget_box_field_out", flags, nullptr);
    ASSERT_EQ(boxes["surfaces"].get<int>(), 2002);
    if (method == "linear") {
      EXPECT_LT(boxes["power_left_out"].get<double>(), 1e-3) << "every surface lit shoots";
    }
    const double data_mib = boxes["bytes"]["total"].get<double>() / kMiB;
    const double beside = boxes["peak_memory_mib"].get<double>() - floor["peak_memory_mib"].get<double>();
    EXPECT_LE(beside, kPeakMargin * data_mib + 8.0) << data_mib << " MiB of data";
  }
}

// A floor with 400 boxes under one lamp (2 002 surfaces, all but the lamp
// reflecting): each box face lit by the lamp shoots, with a first link on
// every floor vertex in front of it. Those first links were made whatever
// the budget, so at --max-memory 8M the data ended at 111 MiB (docs/
// robustness.md, "First links within the memory budget"). Now the faces whose
// first links do not fit wait, the brightest start first, the lamp starts
// whatever the budget, and the run says how much light it left out. (That
// with room every lit face shoots is
// FirstLinksAmongManySurfacesNeedLittleMemoryBesideTheirData.)
TEST(Budgets, ReflectorsWhoseFirstLinksDoNotFitWaitAndTheLightTheyHoldIsReported) {
  constexpr std::size_t kBudget = 8u << 20;
  const auto field = test::fresh_dir("budget_box_field_tight");
  write_box_field(field, true);
  std::string err;
  const nlohmann::json boxes =
      solve_file(field / "boxes.obj", "budget_box_field_tight_out", {"--max-memory", "8M"}, &err);
  ASSERT_EQ(boxes["surfaces"].get<int>(), 2002);
  EXPECT_LE(boxes["bytes"]["total"].get<std::size_t>(), kBudget);
  EXPECT_TRUE(boxes["memory_budget_reached"].get<bool>());
  const std::size_t waiting = boxes["surfaces_left_out_for_memory"].get<std::size_t>();
  const double left_out = boxes["power_left_out_for_memory"].get<double>();
  EXPECT_GT(waiting, 0u);
  EXPECT_LT(waiting, 2001u) << "the brightest reflectors shoot";
  EXPECT_GT(left_out, 0.0);
  // The lamp shoots (what the floor and boxes hold is what it sends them
  // times their reflectance, which is under 1 of what it emits).
  EXPECT_LT(left_out, 1.0);
  EXPECT_NEAR(boxes["power_left_out"].get<double>(), left_out, 1e-3);
  EXPECT_EQ(err.find("the radiosity data ended at"), std::string::npos) << err;
  EXPECT_NE(err.find(std::to_string(waiting) + " surfaces holding "), std::string::npos) << err;
  EXPECT_NE(err.find("do not fit in --max-memory (8 MiB)"), std::string::npos) << err;
}

std::size_t meminfo_total_bytes() {
  std::ifstream in("/proc/meminfo");
  std::string key;
  std::size_t kib = 0;
  while (in >> key) {
    if (key == "MemTotal:" && in >> kib) return kib * 1024;
    in.ignore(std::numeric_limits<std::streamsize>::max(), '\n');
  }
  return 0;
}

TEST(Budgets, TheDefaultMemoryBudgetIsAQuarterOfTheMachineAndIsPrinted) {
  const std::size_t total = meminfo_total_bytes();
  ASSERT_GT(total, 0u);
  const std::size_t machine = machine_memory_bytes();
  EXPECT_GT(machine, 0u);
  EXPECT_LE(machine, total) << "a control group may lower it, never raise it";
  EXPECT_NEAR(static_cast<double>(default_memory_budget()), 0.25 * static_cast<double>(machine), 1.0);

  const auto dir = test::fresh_dir("budget_default");
  test::write_lit_floor_obj(dir);
  std::string err;
  const nlohmann::json by_default = solve_file(dir / "tiny.obj", "budget_default_out", {}, &err);
  EXPECT_EQ(by_default["parameters"]["max_bytes"].get<std::size_t>(), default_memory_budget());
  EXPECT_NE(err.find("memory budget " + format_bytes(default_memory_budget())), std::string::npos) << err;
  const nlohmann::json unlimited = solve_file(dir / "tiny.obj", "budget_none_out", {"--max-memory", "0"}, &err);
  EXPECT_EQ(unlimited["parameters"]["max_bytes"].get<std::size_t>(), 0u);
  EXPECT_EQ(err.find("memory budget"), std::string::npos) << err;
  const nlohmann::json chosen = solve_file(dir / "tiny.obj", "budget_chosen_out", {"--max-memory", "24M"}, &err);
  EXPECT_EQ(chosen["parameters"]["max_bytes"].get<std::size_t>(), std::size_t{24} << 20);
  EXPECT_EQ(err.find("memory budget"), std::string::npos) << "only the default is announced: " << err;
}

TEST(Budgets, ACameraWhoseImageCannotFitIsRefusedBeforeTheWork) {
  // 60000 x 60000 pixels at 64 bytes: 215 GiB.
  if (machine_memory_bytes() > (std::size_t{200} << 30)) GTEST_SKIP() << "this machine could hold the image";
  const auto dir = test::fresh_dir("budget_image");
  test::write_lit_floor_obj(dir);
  test::write_text(dir / "huge.scene.json",
                   R"({"mesh": "tiny.obj", "camera": {"eye": [0.5, 0.5, 3], "target": [0.5, 0.5, 0], )"
                   R"("up": [0, 1, 0], "fov_y_deg": 40, "width": 60000, "height": 60000}})");
  for (const std::string budget : {"auto", "0"}) {
    SCOPED_TRACE(budget);
    const auto out = dir / ("out_" + budget);
    const test::CommandResult r =
        test::run_lhr({"solve", (dir / "huge.scene.json").string(), "--out", out.string(), "--max-memory", budget});
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_EQ(test::count_lines(r.err), 1) << r.err;
    EXPECT_NE(r.err.find("a 60000 x 60000 image needs about"), std::string::npos) << r.err;
    EXPECT_FALSE(std::filesystem::exists(out)) << "refused before the output directory is made";
  }
}

TEST(Budgets, MaxLinksWarnsAndIsRecordedInStats) {
  std::string err;
  const nlohmann::json capped = solve_cornell("budget_links", {"--max-links", "50000"}, &err);
  EXPECT_NE(err.find("warning: --max-links reached"), std::string::npos) << err;
  EXPECT_TRUE(capped["link_budget_reached"].get<bool>());
  EXPECT_FALSE(capped["memory_budget_reached"].get<bool>());
  EXPECT_LE(capped["links"].get<std::size_t>(),
            50000 + kLinkOvershoot + capped["links_linked_past_budget"].get<std::size_t>());
}

// 400 small lamps in one plane over a floor, written as lamps.obj in `dir`.
// In one group they are one surface (docs/design.md §3, "Panels of lights");
// each in a group of its own, they are 400 surfaces.
void write_lamps(const std::filesystem::path& dir, bool group_each) {
  std::ostringstream obj;
  obj << "mtllib lamps.mtl\nv -5 0 -5\nv 5 0 -5\nv 5 0 5\nv -5 0 5\nusemtl floor\nf 1 4 3 2\nusemtl lamp\n";
  int n = 4;
  for (int i = 0; i < 20; ++i) {
    for (int j = 0; j < 20; ++j) {
      const double x = -4.75 + 0.5 * i, z = -4.75 + 0.5 * j, a = 0.015, y = 2.0;
      if (group_each) obj << "g lamp" << n << "\nusemtl lamp\n";
      obj << "v " << x - a << ' ' << y << ' ' << z - a << "\nv " << x + a << ' ' << y << ' ' << z - a << "\nv " << x + a
          << ' ' << y << ' ' << z + a << "\nv " << x - a << ' ' << y << ' ' << z + a << "\nf " << n + 1 << ' ' << n + 2
          << ' ' << n + 3 << ' ' << n + 4 << '\n';
      n += 4;
    }
  }
  std::ofstream(dir / "lamps.obj") << obj.str();
  std::ofstream(dir / "lamps.mtl") << "newmtl floor\nKd 0.7 0.7 0.7\nnewmtl lamp\nKd 0 0 0\nKe 10 10 10\n";
}

// 400 small lamps over a floor, each in a group of its own
// (docs/robustness.md, "Budgets"): each lamp's first links reach the floor's initial vertices
// whatever the budget, or its light would be lost, so under --max-memory 1M
// the data ends over it (6 MB) without any refinement being refused. The run
// must say so, in stats.json and in a warning naming both sizes; it said
// nothing before.
TEST(Budgets, FirstLinksOverTheMemoryBudgetAreReportedAndWarned) {
  const auto dir = test::fresh_dir("budget_lamps");
  write_lamps(dir, true);
  std::string err;
  const nlohmann::json stats = solve_file(dir / "lamps.obj", "budget_lamps_out", {"--max-memory", "1M"}, &err);
  EXPECT_TRUE(stats["memory_budget_reached"].get<bool>());
  EXPECT_GT(stats["bytes"]["total"].get<double>(), 1024.0 * 1024.0);
  // Every lamp lights the floor: one link at least from each.
  EXPECT_GE(stats["links"].get<std::size_t>(), 400u);
  EXPECT_NE(err.find("warning: the radiosity data ended at"), std::string::npos) << err;
  EXPECT_NE(err.find("over --max-memory (1 MiB)"), std::string::npos) << err;
}

// The same 400 lamps in one plane are one shooter (docs/design.md §3, "Panels
// of lights"): one graph on the floor, whose links open the panel's clusters
// only where the floor needs them. As 400 shooters their first links alone
// (6 MB) were over a 4M budget before anything was refined; as one the whole
// solve fits in it, refined. (That a panel delivers each lamp's power is
// SmallLights.APanelOfSmallLightsIsOneSurfaceThatDeliversEachLampsPower.)
TEST(Budgets, CoplanarLampsAreOneShooterAndStayWithinTheMemoryBudget) {
  constexpr double kBudget = 4.0 * 1024 * 1024;
  const auto separate_dir = test::fresh_dir("budget_lamps_apart");
  write_lamps(separate_dir, true);
  std::string err;
  const nlohmann::json separate =
      solve_file(separate_dir / "lamps.obj", "budget_lamps_apart_out", {"--max-memory", "4M", "--max-links", "1"}, &err);
  EXPECT_EQ(separate["surfaces"].get<int>(), 401);
  EXPECT_GT(separate["bytes"]["total"].get<double>(), kBudget) << "the premise: 400 shooters' first links";

  const auto panel_dir = test::fresh_dir("budget_lamp_panel");
  write_lamps(panel_dir, false);
  const nlohmann::json panel = solve_file(panel_dir / "lamps.obj", "budget_lamp_panel_out", {"--max-memory", "4M"}, &err);
  EXPECT_EQ(panel["surfaces"].get<int>(), 2);
  EXPECT_LE(panel["bytes"]["total"].get<double>(), kBudget);
  EXPECT_EQ(err.find("the radiosity data ended at"), std::string::npos) << err;
  // Refined past the first links (520: one per initial floor vertex).
  EXPECT_GT(panel["links"].get<std::size_t>(), 2000u) << err;
}

TEST(Budgets, MaxMemoryTakesSizesAndRejectsNonsense) {
  const auto dir = test::fresh_dir("budget_flags");
  for (const std::string bad : {"-1", "12X", "lots", "1e400"}) {
    const auto r = test::run_lhr({"solve", (test::source_dir() / "data/cornell/cornell.scene.json").string(), "--out",
                                  dir.string(), "--max-memory", bad});
    EXPECT_EQ(r.exit_code, 2) << bad << ": " << r.err;
    EXPECT_NE(r.err.find("--max-memory must be a size"), std::string::npos) << r.err;
    EXPECT_EQ(test::count_lines(r.err), 1) << r.err;
  }
}

// A scene of many small shooters (thousands of lamps over one floor) holds
// one graph per lamp, most of which never split: each must cost its
// receiver's initial vertices and nothing more. Growth by doubling left up
// to half of every per-vertex table unused (10 000 lamps: 637 MB of graphs
// for 104 MB of links, then 362 MB, 259 MB with the links in one array, and
// 106 MB with the roots and initial vertices shared and gathered values in
// float; docs/robustness.md, "Budgets").
TEST(Budgets, AGraphOnItsReceiversRootsHoldsNoSpareRoom) {
  constexpr int kSide = 21;  // 441 vertices, 800 roots: not a power of two
  SurfaceHierarchy receiver = test::grid_hierarchy(kSide);
  // Other graphs have refined the receiver already: its vertex and node
  // tables are longer than this graph needs.
  for (int f = 0; f < 50; ++f) receiver.split(receiver.root(f));
  const InteractionGraph graph(0, 1, receiver);
  const std::size_t vertices = static_cast<std::size_t>(kSide) * kSide;
  const std::size_t roots = receiver.num_roots();
  ASSERT_EQ(graph.num_vertices(), vertices);
  ASSERT_EQ(graph.num_leaves(), roots);
  // Per vertex: where its links start in the graph's one link array (a
  // 32-bit offset, not a vector of its own); its gathered value is summed
  // from the links where it is read. The roots, the vertex ids and their
  // index are the receiver's Start, shared by every graph on it.
  const std::size_t per_vertex = sizeof(std::uint32_t);
  EXPECT_LE(graph.bytes(), sizeof(InteractionGraph) + sizeof(std::uint32_t) + vertices * per_vertex);
  EXPECT_GE(graph.start().bytes(), roots * sizeof(NodeId) + vertices * (sizeof(VertexId) + sizeof(std::int32_t)));
}

// A strip of two triangles: four vertices, two roots.
SurfaceHierarchy two_triangles() {
  TriMesh mesh;
  const auto a = mesh.add_vertex(Vec3(0, 0, 0)), b = mesh.add_vertex(Vec3(1, 0, 0));
  const auto c = mesh.add_vertex(Vec3(1, 0, 1)), d = mesh.add_vertex(Vec3(0, 0, 1));
  mesh.add_face(a, c, b);
  mesh.add_face(a, d, c);
  return SurfaceHierarchy(std::move(mesh));
}

std::vector<NodeId> shooters_of(const InteractionGraph& g, int i) {
  std::vector<NodeId> out;
  for (const GraphLink& l : g.links(i)) out.push_back(l.shooter);
  return out;
}

TEST(Budgets, GraphLinksGrowInOrderAndPackIntoOneArrayWithNoSpareRoom) {
  SurfaceHierarchy receiver = two_triangles();
  InteractionGraph g(0, 1, receiver);
  ASSERT_EQ(g.num_vertices(), 4u);
  g.set_every_vertex_link({kWholeSurface, {}});
  EXPECT_EQ(g.num_links(), 4u);
  EXPECT_EQ(g.link_bytes(), 4 * sizeof(GraphLink));
  // A shooter split: the first link becomes a child, three more follow. The
  // grown list is seen at once, before it is packed.
  g.links(1)[0] = {10, {}};
  for (NodeId kid : {11, 12, 13}) g.add_link(1, {kid, {}});
  g.add_link(3, {20, {}});
  EXPECT_EQ(shooters_of(g, 1), (std::vector<NodeId>{10, 11, 12, 13}));
  EXPECT_EQ(shooters_of(g, 3), (std::vector<NodeId>{kWholeSurface, 20}));
  EXPECT_EQ(g.num_links(), 8u);
  // A receiver split: each new vertex starts from its seed's links.
  std::vector<InteractionGraph::NewVertex> created;
  ASSERT_TRUE(g.split(receiver.root(0), receiver, created));
  ASSERT_FALSE(created.empty());
  for (const auto& nv : created) {
    const std::vector<NodeId> seed = shooters_of(g, nv.seed);
    std::vector<GraphLink> links;
    for (NodeId e : seed) links.push_back({e, {}});
    g.set_links(nv.index, links);
    EXPECT_EQ(shooters_of(g, nv.index), seed);
  }
  EXPECT_THROW(g.set_links(created[0].index, std::vector<GraphLink>{{30, {}}}), std::logic_error);
  std::vector<std::vector<NodeId>> before;
  for (int i = 0; i < static_cast<int>(g.num_vertices()); ++i) before.push_back(shooters_of(g, i));
  const std::size_t links = g.num_links();
  g.pack_links();
  for (int i = 0; i < static_cast<int>(g.num_vertices()); ++i) EXPECT_EQ(shooters_of(g, i), before[i]) << i;
  EXPECT_EQ(g.num_links(), links);
  EXPECT_EQ(g.link_bytes(), links * sizeof(GraphLink));
}

}  // namespace
}  // namespace lhr

namespace lhr {
namespace {

// bytes.graphs counts, beside each graph's own tables, the receivers'
// shared starts and the unoccluded form factors kept at the receiver
// vertices that are not graph vertices (16 bits each). The importance per
// graph vertex (16 bits each) is held only while a refinement runs, for the
// graphs the shooter oracle judges; the memory budget, planned then, must
// see it, and once the solve is done it is gone (BENCHMARKS.md, "Graph
// storage under 30 %").
TEST(Budgets, GraphBytesCountTheCachesAndTheImportanceWhileRefining) {
  const Scene scene = test::furnace_cube(0.5, 1.0);
  MeshingOptions meshing;
  meshing.max_edge = 0.25;
  MeshedScene model(scene, meshing);
  LinearOptions options;
  options.max_bytes = std::size_t{1} << 40;  // so that the plan counts the bytes
  const LinearSolver* watched = nullptr;
  std::size_t largest_while_refining = 0;
  // Called inside refine(), after the plan: the stats then are the plan's.
  options.checkpoint = [&] {
    if (watched != nullptr) largest_while_refining = std::max(largest_while_refining, watched->stats().bytes_graphs);
  };
  LinearSolver solver(model, options);
  watched = &solver;
  solver.solve();
  std::size_t counted = 0, vertices = 0;
  std::set<const InteractionGraph::Start*> starts;
  for (const InteractionGraph& g : solver.graphs()) {
    counted += g.bytes();
    if (starts.insert(&g.start()).second) counted += g.start().bytes();
    const std::size_t receiver_vertices = model.hierarchy(g.receiver_surface()).num_vertices();
    counted += (receiver_vertices - g.num_vertices()) * sizeof(UnitFloat16);
    vertices += g.num_vertices();
  }
  const LinearStats& stats = solver.stats();
  ASSERT_EQ(stats.graph_vertices, vertices);
  EXPECT_GE(stats.bytes_graphs, counted);
  // The rest: a few words per graph (the caches' and tables' headers).
  const std::size_t headers = solver.graphs().size() * 16 * sizeof(void*);
  EXPECT_LE(stats.bytes_graphs, counted + headers);
  // While refining, every graph was judged at least once with its
  // importance held: at the first refinement all of them are.
  ASSERT_GT(stats.iterations, 2);
  EXPECT_GE(largest_while_refining, stats.bytes_graphs + vertices / 2 * sizeof(BFloat16));
}

}  // namespace
}  // namespace lhr
