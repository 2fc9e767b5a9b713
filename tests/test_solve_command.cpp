// `lhr solve` end to end: the five outputs, their contracts, and results that
// do not depend on the thread count.

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <filesystem>
#include <regex>
#include <string>

#include "io/image_io.hpp"
#include "io/mesh_io.hpp"
#include "mesh/validate.hpp"
#include "test_support.hpp"

namespace lhr {
namespace {

// A quick Cornell box: coarse initial mesh, coarse thresholds.
std::vector<std::string> quick_cornell(const std::string& out, int threads, const std::string& method) {
  return {"solve", (test::source_dir() / "data/cornell/cornell.scene.json").string(), "--out", out,
          "--method", method, "--max-edge", "140", "--eps-bf", "0.02", "--eps-link", "40",
          "--threads", std::to_string(threads), "--quiet"};
}

const char* const kMethods[] = {"linear", "classical"};

// The VERSION of project() in the top CMakeLists.txt, read independently.
std::string project_version() {
  const std::string cmake = test::read_text(test::source_dir() / "CMakeLists.txt");
  std::smatch m;
  if (!std::regex_search(cmake, m, std::regex(R"(project\(lhr VERSION ([0-9.]+))"))) return "not found";
  return m[1];
}

TEST(Command, VersionIsTheProjectVersion) {
  const auto r = test::run_lhr({"--version"});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.out, "lhr " + project_version() + "\n");
}

TEST(Command, HelpListsTheExitStatuses) {
  const auto r = test::run_lhr({"--help"});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  for (const char* status : {"exit status: 0", "; 1 bad input", "; 2 a bad command line", "; 130 stopped"}) {
    EXPECT_NE(r.out.find(status), std::string::npos) << status << " in\n" << r.out;
  }
  // And they are what a command returns.
  EXPECT_EQ(test::run_lhr({"solve", "--no-such-flag"}).exit_code, 2);
  EXPECT_EQ(test::run_lhr({"validate", (test::source_dir() / "no-such-file.ply").string()}).exit_code, 1);
}

TEST(Command, HelpShowsDefaultsAsWritten) {
  // Boost prints a double default at full precision: 2.2000000000000002.
  for (const char* command : {"solve", "mesh", "validate", "reference", "compare", "bench", "scene"}) {
    SCOPED_TRACE(command);
    const auto r = test::run_lhr({command, "--help"});
    EXPECT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(r.out.find("00000"), std::string::npos) << r.out;
    EXPECT_EQ(r.out.find("99999"), std::string::npos) << r.out;
  }
  const auto solve = test::run_lhr({"solve", "--help"});
  EXPECT_NE(solve.out.find("(=2.2)"), std::string::npos) << solve.out;
  const auto validate = test::run_lhr({"validate", "--help"});
  EXPECT_NE(validate.out.find("(=1e-06)"), std::string::npos) << validate.out;
}

TEST(Command, SceneCreatesItsOutputDirectory) {
  const auto dir = test::fresh_dir("scene_out_dir") / "not" / "yet";
  const auto r = test::run_lhr({"scene", "two-rooms", "--out-dir", dir.string()});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(std::filesystem::exists(dir / "two-rooms.scene.json"));
}

nlohmann::json without_timings(nlohmann::json stats) {
  stats.erase("seconds");
  stats.erase("peak_memory_mib");
  return stats;
}

TEST(SolveCommand, WritesTheFiveOutputsWithTheirContracts) {
  for (const std::string method : kMethods) {
    SCOPED_TRACE(method);
    const auto dir = test::fresh_dir("solve_outputs_" + method);
    const auto r = test::run_lhr(quick_cornell((dir / "c").string(), 0, method));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    for (const char* name : {"mesh.ply", "mesh.off", "image.png", "image.exr", "stats.json"}) {
      EXPECT_TRUE(std::filesystem::exists(dir / "c" / name)) << name;
    }
    // The exported mesh is conforming and carries finite, non-negative radiance.
    const RawMesh mesh = read_raw_mesh(dir / "c" / "mesh.ply");
    ASSERT_EQ(mesh.radiance.size(), mesh.points.size());
    ConformingCheckOptions check;
    check.relative_tolerance = 1e-6;  // coordinates went through float storage
    const auto violations = check_conforming_mesh(mesh, check);
    EXPECT_TRUE(violations.empty()) << (violations.empty() ? "" : format_violation(violations.front()));
    const std::string ply = test::read_text(dir / "c" / "mesh.ply");
    const std::string header = ply.substr(0, ply.find("end_header"));
    for (const char* property : {"property uchar red", "property uchar green", "property uchar blue",
                                 "property float radiance_r", "property float radiance_g",
                                 "property float radiance_b"}) {
      EXPECT_NE(header.find(property), std::string::npos) << property;
    }
    // The header says what the colours are, with the tone map actually used.
    EXPECT_NE(header.find("comment red green blue: display colour, tone-mapped tumblin-rushmeier ("),
              std::string::npos)
        << header;
    EXPECT_NE(header.find("gamma 2.2)"), std::string::npos) << header;
    // The light is seen: the brightest pixel is the light's radiance (Ke 17 12 4)
    // plus the little it reflects (Kd 0.78 of the dim room around it).
    const Image exr = read_image(dir / "c" / "image.exr");
    float brightest = 0;
    for (float v : exr.rgb) brightest = std::max(brightest, v);
    EXPECT_GE(brightest, 17.0f - 0.02f);
    EXPECT_LT(brightest, 17.5f);
    const auto stats = nlohmann::json::parse(test::read_text(dir / "c" / "stats.json"));
    EXPECT_EQ(stats["method"], method);
    EXPECT_GT(stats["links"].get<long>(), 0);
    EXPECT_EQ(stats["exported_triangles"].get<std::size_t>(), mesh.faces.size());
    EXPECT_EQ(stats.value("lhr_version", std::string()), project_version());
  }
}

TEST(SolveCommand, TheLinearMethodIsTheDefault) {
  const auto dir = test::fresh_dir("solve_default");
  const auto r = test::run_lhr({"solve", (test::source_dir() / "data/cornell/cornell.scene.json").string(), "--out",
                                (dir / "d").string(), "--max-edge", "140", "--eps-link", "40", "--quiet"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto stats = nlohmann::json::parse(test::read_text(dir / "d" / "stats.json"));
  EXPECT_EQ(stats["method"], "linear");
  for (const char* key : {"graphs", "graph_vertices", "elements_per_level", "bytes"}) {
    EXPECT_TRUE(stats.contains(key)) << key;
  }
  for (const char* phase : {"coefficients", "gather", "push_pull", "oracles"}) {
    EXPECT_TRUE(stats["seconds"].contains(phase)) << phase;
  }
  const auto unknown = test::run_lhr({"solve", (test::source_dir() / "data/cornell/cornell.scene.json").string(),
                                      "--out", (dir / "u").string(), "--method", "galerkin"});
  EXPECT_EQ(unknown.exit_code, 2);
  EXPECT_NE(unknown.err.find("--method"), std::string::npos) << unknown.err;
}

// Statistics of a short, coarse Cornell box solve as made and with `flag`.
struct StatsPair {
  nlohmann::json as_made, flagged;
};
StatsPair coarse_cornell_with_and_without(const std::string& name, const std::string& flag) {
  const auto dir = test::fresh_dir(name);
  const std::string scene = (test::source_dir() / "data/cornell/cornell.scene.json").string();
  const std::vector<std::string> coarse{"--max-edge", "140", "--eps-link", "160", "--eps-pixel", "4",
                                        "--max-iterations", "5", "--quiet"};
  StatsPair out;
  for (const bool with : {false, true}) {
    const std::filesystem::path d = dir / (with ? "f" : "m");
    std::vector<std::string> args{"solve", scene, "--out", d.string()};
    if (with) args.push_back(flag);
    args.insert(args.end(), coarse.begin(), coarse.end());
    const auto run = test::run_lhr(args);
    EXPECT_EQ(run.exit_code, 0) << run.err;
    (with ? out.flagged : out.as_made) =
        run.exit_code == 0 ? nlohmann::json::parse(test::read_text(d / "stats.json")) : nlohmann::json::object();
  }
  return out;
}

// --redraw-cluster-links reaches the solver: the same solve draws every
// cluster link again in every iteration, so it traces more shadow rays
// (docs/accuracy.md, "A shape factor that ages").
TEST(SolveCommand, RedrawClusterLinksTracesTheirRaysAgain) {
  const StatsPair stats = coarse_cornell_with_and_without("solve_redraw", "--redraw-cluster-links");
  ASSERT_TRUE(stats.as_made.contains("iterations") && stats.flagged.contains("shadow_rays"));
  ASSERT_GT(stats.as_made["iterations"].get<int>(), 1);
  EXPECT_GT(stats.flagged["shadow_rays"].get<double>(), 1.2 * stats.as_made["shadow_rays"].get<double>());
}

// --rescale-cluster-links reaches the solver: cluster links are rescaled
// as the light's shape changes over the bounces, and none are without it.
TEST(SolveCommand, RescaleClusterLinksRescalesThem) {
  const StatsPair stats = coarse_cornell_with_and_without("solve_rescale", "--rescale-cluster-links");
  ASSERT_TRUE(stats.as_made.contains("cluster_links_rescaled") && stats.flagged.contains("cluster_links_rescaled"));
  EXPECT_EQ(stats.as_made["cluster_links_rescaled"].get<std::size_t>(), 0u);
  EXPECT_GT(stats.flagged["cluster_links_rescaled"].get<std::size_t>(), 0u);
}

TEST(SolveCommand, ThreadCountDoesNotChangeTheResult) {
  for (const std::string method : kMethods) {
    SCOPED_TRACE(method);
    const auto dir = test::fresh_dir("solve_threads_" + method);
    const auto one = test::run_lhr(quick_cornell((dir / "t1").string(), 1, method));
    const auto two = test::run_lhr(quick_cornell((dir / "t2").string(), 2, method));
    ASSERT_EQ(one.exit_code, 0) << one.err;
    ASSERT_EQ(two.exit_code, 0) << two.err;
    EXPECT_EQ(without_timings(nlohmann::json::parse(test::read_text(dir / "t1" / "stats.json"))),
              without_timings(nlohmann::json::parse(test::read_text(dir / "t2" / "stats.json"))));
    // Pixels bit for bit (the EXR header carries a capture date).
    EXPECT_TRUE(read_image(dir / "t1" / "image.exr").rgb == read_image(dir / "t2" / "image.exr").rgb);
    EXPECT_TRUE(test::read_text(dir / "t1" / "mesh.ply") == test::read_text(dir / "t2" / "mesh.ply"));
    EXPECT_TRUE(test::read_text(dir / "t1" / "image.png") == test::read_text(dir / "t2" / "image.png"));
  }
}

// The outputs' contracts and their independence of the thread count on a
// scene small enough for the sanitized build, where the Cornell box runs
// above take minutes (docs/robustness.md, "What runs where").
TEST(SolveCommand, TinySceneWritesTheSameFiveOutputsForAnyThreadCount) {
  const auto dir = test::fresh_dir("solve_tiny");
  test::write_lit_floor_obj(dir);
  test::write_text(dir / "tiny.scene.json", "{\"mesh\": \"tiny.obj\", \"camera\": {\"eye\": [0.5, -0.3, 0.3], "
                                            "\"target\": [0.5, 0.5, 0.15], \"up\": [0, 0, 1], \"fov_y_deg\": 90, "
                                            "\"width\": 32, \"height\": 24}}\n");
  for (const std::string method : kMethods) {
    SCOPED_TRACE(method);
    const auto run = [&](int threads) {
      const auto out = dir / (method + std::to_string(threads));
      const auto r = test::run_lhr({"solve", (dir / "tiny.scene.json").string(), "--out", out.string(), "--method",
                                    method, "--eps-bf", "0.02", "--threads", std::to_string(threads), "--quiet"});
      EXPECT_EQ(r.exit_code, 0) << r.err;
      return out;
    };
    const auto one = run(1), two = run(2);
    for (const char* name : {"mesh.ply", "mesh.off", "image.png", "image.exr", "stats.json"}) {
      ASSERT_TRUE(std::filesystem::exists(one / name)) << name;
    }
    const RawMesh mesh = read_raw_mesh(one / "mesh.ply");
    ASSERT_EQ(mesh.radiance.size(), mesh.points.size());
    ConformingCheckOptions check;
    check.relative_tolerance = 1e-6;  // coordinates went through float storage
    const auto violations = check_conforming_mesh(mesh, check);
    EXPECT_TRUE(violations.empty()) << (violations.empty() ? "" : format_violation(violations.front()));
    // The camera sees the light's underside: Ke 3 and Kd 0, so exactly its emission.
    const Image exr = read_image(one / "image.exr");
    float brightest = 0;
    for (float v : exr.rgb) brightest = std::max(brightest, v);
    EXPECT_NEAR(brightest, 3.0f, 1e-4f);
    const auto stats = nlohmann::json::parse(test::read_text(one / "stats.json"));
    EXPECT_EQ(stats["method"], method);
    EXPECT_GT(stats["links"].get<long>(), 0);
    EXPECT_EQ(stats["exported_triangles"].get<std::size_t>(), mesh.faces.size());

    EXPECT_EQ(without_timings(stats), without_timings(nlohmann::json::parse(test::read_text(two / "stats.json"))));
    EXPECT_TRUE(exr.rgb == read_image(two / "image.exr").rgb);
    EXPECT_TRUE(test::read_text(one / "mesh.ply") == test::read_text(two / "mesh.ply"));
    EXPECT_TRUE(test::read_text(one / "image.png") == test::read_text(two / "image.png"));
  }
}

TEST(SolveCommand, BadInputFailsInOneLineAndWritesNothing) {
  const auto dir = test::fresh_dir("solve_bad");
  test::write_text(dir / "broken.obj", "v 0 0 0\nv 1 0 0\nf 1 2 3\n");
  const auto r = test::run_lhr({"solve", (dir / "broken.obj").string(), "--out", (dir / "out").string()});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(test::count_lines(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("broken.obj"), std::string::npos);
  EXPECT_FALSE(std::filesystem::exists(dir / "out" / "mesh.ply"));
}

}  // namespace
}  // namespace lhr

namespace lhr {
namespace {

TEST(SolveCommand, ToneMapComesFromTheSceneFileUnlessAFlagSaysOtherwise) {
  // A lit floor (test::write_lit_floor_obj): small enough to run sanitized.
  const auto dir = test::fresh_dir("solve_tone");
  test::write_lit_floor_obj(dir);
  test::write_text(dir / "lin.scene.json",
                   "{\"mesh\": \"tiny.obj\", \"camera\": {\"eye\": [0.5, -0.3, 0.3], \"target\": [0.5, 0.5, 0.15], "
                   "\"up\": [0, 0, 1], \"fov_y_deg\": 90, \"width\": 32, \"height\": 24}, "
                   "\"tone_map\": {\"kind\": \"linear\", \"white\": 5, \"gamma\": 1.8}}");
  std::string err;
  const auto run = [&](const std::string& out, std::vector<std::string> extra) {
    std::vector<std::string> args{"solve", (dir / "lin.scene.json").string(), "--out", (dir / out).string()};
    args.insert(args.end(), extra.begin(), extra.end());
    const auto r = test::run_lhr(args);
    EXPECT_EQ(r.exit_code, 0) << r.err;
    err = r.err;
    return nlohmann::json::parse(test::read_text(dir / out / "stats.json"))["parameters"]["tone_map"]
        .get<std::string>();
  };
  EXPECT_EQ(run("file", {"--quiet"}), "linear (white 5, gamma 1.8)");
  EXPECT_EQ(run("flag", {"--white", "7", "--quiet"}), "linear (white 7, gamma 1.8)");
  EXPECT_EQ(run("kind", {"--tone-map", "tumblin-rushmeier", "--verbose"}).rfind("tumblin-rushmeier", 0), 0u);
  EXPECT_NE(err.find("iteration 1: largest change"), std::string::npos) << "--verbose reports each iteration: " << err;

  test::write_text(dir / "bad.scene.json", "{\"mesh\": \"tiny.obj\", \"tone_map\": {\"kind\": \"reinhardt\"}}");
  const auto bad = test::run_lhr({"solve", (dir / "bad.scene.json").string(), "--out", (dir / "bad").string()});
  EXPECT_EQ(bad.exit_code, 1);
  EXPECT_EQ(test::count_lines(bad.err), 1) << bad.err;
  EXPECT_NE(bad.err.find("tone_map.kind"), std::string::npos) << bad.err;
}

}  // namespace
}  // namespace lhr
