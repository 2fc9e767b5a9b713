// An interrupted `lhr solve`, `lhr mesh` or `lhr reference`, of an image or
// at a mesh's vertices (SIGINT or SIGTERM mid-run)
// exits cleanly with code 130, writes no file, and leaves an existing output
// untouched.

#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include "test_support.hpp"

namespace lhr {
namespace {

struct Interrupted {
  int exit_code = -1;
  std::string err;
  double seconds_to_stop = 0.0;  // from the signal to the exit
};

// True once process pid has a handler for signal (its SigCgt mask in
// /proc/PID/status): a signal sent earlier would take the default action.
bool catches(pid_t pid, int signal) {
  const std::string status = test::read_text("/proc/" + std::to_string(pid) + "/status");
  const auto at = status.find("SigCgt:");
  if (at == std::string::npos) return false;
  const unsigned long long mask = std::stoull(status.substr(at + 7), nullptr, 16);
  return (mask >> (signal - 1)) & 1u;
}

// Starts `lhr` with args (a run of many seconds) and signals it `delay`
// after `marker` appears on its stderr (an empty marker: after it installs
// its handler for the signal): the run is then mid-work.
Interrupted interrupt_run(const std::filesystem::path& dir, std::vector<std::string> args, const std::string& marker,
                          int signal, std::chrono::milliseconds delay) {
  const std::string err_file = (dir / "stderr.txt").string();
  const pid_t pid = test::spawn_lhr(std::move(args), err_file);
  Interrupted result;
  if (pid < 0) return result;
  for (int waited = 0; waited < 600; ++waited) {
    if (marker.empty() ? catches(pid, signal) : test::read_text(err_file).find(marker) != std::string::npos) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  std::this_thread::sleep_for(delay);
  const auto signalled = std::chrono::steady_clock::now();
  kill(pid, signal);
  int status = 0;
  waitpid(pid, &status, 0);
  result.seconds_to_stop = std::chrono::duration<double>(std::chrono::steady_clock::now() - signalled).count();
  result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  result.err = test::read_text(err_file);
  return result;
}

TEST(Interrupt, SignalMidSolveExitsCleanlyAndKeepsOldOutputs) {
  for (const int signal : {SIGINT, SIGTERM}) {
    SCOPED_TRACE(signal);
    const auto dir = test::fresh_dir("interrupt_" + std::to_string(signal));
    // An earlier run's result must survive.
    std::filesystem::create_directories(dir / "out");
    test::write_text(dir / "out" / "mesh.ply", "earlier result");
    const std::string scene = (test::source_dir() / "data/cornell/cornell.scene.json").string();
    const Interrupted r = interrupt_run(
        dir, {"solve", scene, "--out", (dir / "out").string(), "--eps-link", "5", "--verbose"}, "iteration 1:",
        signal, std::chrono::milliseconds(200));
    EXPECT_EQ(r.exit_code, 130) << r.err;
    EXPECT_NE(r.err.find("interrupted"), std::string::npos) << r.err;
    EXPECT_EQ(test::read_text(dir / "out" / "mesh.ply"), "earlier result");
    EXPECT_EQ(test::file_names(dir / "out"), std::vector<std::string>{"mesh.ply"}) << "no new, partial or temporary file";
  }
}

// Sanitized builds run several times slower: there the bound on how soon
// a run stops is not checked, only that it stops cleanly.
constexpr bool kTimingMeaningful = !test::kUnderAddressSanitizer;

TEST(Interrupt, ClassicalStopsWithinASecondMidRefinement) {
  // A closed cube whose six faces glow (Le 1) and reflect (rho 0.5): with no
  // budget, BF refinement never ends on it, and each pass computes the
  // coefficients of hundreds of thousands of new links, which used to run
  // to the end of the iteration before a signal was seen.
  const auto dir = test::fresh_dir("interrupt_classical");
  test::write_glowing_cube(dir);
  const Interrupted r = interrupt_run(dir,
                                      {"solve", (dir / "cube.obj").string(), "--out", (dir / "out").string(),
                                       "--method", "classical", "--max-memory", "0", "--verbose"},
                                      "", SIGINT, std::chrono::milliseconds(2000));
  EXPECT_EQ(r.exit_code, 130) << r.err;
  EXPECT_NE(r.err.find("interrupted"), std::string::npos) << r.err;
  // Its first iteration refines for minutes: the signal lands inside it.
  EXPECT_EQ(r.err.find("iteration 1:"), std::string::npos) << "the signal should land mid-iteration: " << r.err;
  RecordProperty("seconds_to_stop", std::to_string(r.seconds_to_stop));
  if (kTimingMeaningful) {
    EXPECT_LT(r.seconds_to_stop, 1.0);
  }
  EXPECT_TRUE(test::file_names(dir / "out").empty()) << "no new, partial or temporary file";
}

TEST(Interrupt, SignalMidReferenceExitsCleanlyAndKeepsTheOldImage) {
  for (const int signal : {SIGINT, SIGTERM}) {
    SCOPED_TRACE(signal);
    const auto dir = test::fresh_dir("interrupt_reference_" + std::to_string(signal));
    std::filesystem::create_directories(dir / "out");
    test::write_text(dir / "out" / "ref.exr", "earlier result");
    const std::string scene = (test::source_dir() / "data/cornell/cornell.scene.json").string();
    // A million samples per pixel: hours, so the signal lands mid-render.
    const Interrupted r = interrupt_run(dir,
                                        {"reference", scene, "--out", (dir / "out" / "ref.exr").string(), "--png",
                                         (dir / "out" / "ref.png").string(), "--spp", "1000000", "--verbose"},
                                        "rendering", signal, std::chrono::milliseconds(200));
    EXPECT_EQ(r.exit_code, 130) << r.err;
    EXPECT_NE(r.err.find("interrupted"), std::string::npos) << r.err;
    EXPECT_EQ(test::read_text(dir / "out" / "ref.exr"), "earlier result");
    EXPECT_EQ(test::file_names(dir / "out"), std::vector<std::string>{"ref.exr"}) << "no new, partial or temporary file";
  }
}

TEST(Interrupt, SignalMidVertexReferenceExitsCleanlyAndKeepsTheOldMesh) {
  const auto dir = test::fresh_dir("interrupt_vertex_reference");
  const std::string scene = (test::source_dir() / "data/cornell/cornell.scene.json").string();
  const auto mesh = (dir / "mesh.ply").string();
  ASSERT_EQ(test::run_lhr({"mesh", scene, "--out", mesh}).exit_code, 0);
  std::filesystem::create_directories(dir / "out");
  test::write_text(dir / "out" / "ref.ply", "earlier result");
  // A million samples per vertex: hours, so the signal lands mid-run.
  const Interrupted r = interrupt_run(dir,
                                      {"reference", scene, "--at-vertices", mesh, "--out",
                                       (dir / "out" / "ref.ply").string(), "--spp", "1000000", "--verbose"},
                                      "tracing", SIGINT, std::chrono::milliseconds(200));
  EXPECT_EQ(r.exit_code, 130) << r.err;
  EXPECT_NE(r.err.find("interrupted"), std::string::npos) << r.err;
  EXPECT_EQ(test::read_text(dir / "out" / "ref.ply"), "earlier result");
  EXPECT_EQ(test::file_names(dir / "out"), std::vector<std::string>{"ref.ply"}) << "no new, partial or temporary file";
}

TEST(Interrupt, SignalMidMeshExitsCleanlyAndLeavesNoTemporary) {
  // 400 separate small squares under a light, meshed finely: many surfaces,
  // so the run is seconds long and checks for a signal between them.
  const auto dir = test::fresh_dir("interrupt_mesh");
  test::write_text(dir / "many.mtl", "newmtl floor\nKd 0.7 0.6 0.5\nnewmtl light\nKd 0 0 0\nKe 3 3 3\n");
  std::string obj = "mtllib many.mtl\nusemtl floor\n";
  int n = 0;
  for (int i = 0; i < 20; ++i) {
    for (int j = 0; j < 20; ++j) {
      const double x = 0.05 * i, y = 0.05 * j;
      for (const auto& [dx, dy] : {std::pair{0.0, 0.0}, {0.04, 0.0}, {0.04, 0.04}, {0.0, 0.04}}) {
        obj += "v " + std::to_string(x + dx) + " " + std::to_string(y + dy) + " 0\n";
      }
      obj += "f " + std::to_string(n + 1) + " " + std::to_string(n + 2) + " " + std::to_string(n + 3) + " " +
             std::to_string(n + 4) + "\n";
      n += 4;
    }
  }
  obj += "usemtl light\nv 0.2 0.2 0.5\nv 0.2 0.8 0.5\nv 0.8 0.8 0.5\nv 0.8 0.2 0.5\nf -4 -3 -2 -1\n";
  test::write_text(dir / "many.obj", obj);
  for (const int signal : {SIGINT, SIGTERM}) {
    SCOPED_TRACE(signal);
    std::filesystem::remove_all(dir / "out");
    std::filesystem::create_directories(dir / "out");
    test::write_text(dir / "out" / "mesh.ply", "earlier result");
    const Interrupted r = interrupt_run(dir,
                                        {"mesh", (dir / "many.obj").string(), "--out",
                                         (dir / "out" / "mesh.ply").string(), "--max-edge", "0.002"},
                                        "", signal, std::chrono::milliseconds(300));
    EXPECT_EQ(r.exit_code, 130) << r.err;
    EXPECT_NE(r.err.find("interrupted"), std::string::npos) << r.err;
    EXPECT_EQ(test::read_text(dir / "out" / "mesh.ply"), "earlier result");
    EXPECT_EQ(test::file_names(dir / "out"), std::vector<std::string>{"mesh.ply"}) << "no new, partial or temporary file";
  }
}

// `lhr mesh` of DIR/NAME, sent SIGTERM `delay` after it catches the
// signal: it exits 130 within `limit` seconds (where timings mean anything)
// and writes nothing.
void expect_mesh_stops_within(const std::filesystem::path& dir, const std::string& name,
                              std::chrono::milliseconds delay, double limit,
                              const std::vector<std::string>& extra = {}) {
  std::filesystem::create_directories(dir / "out");
  std::vector<std::string> args{"mesh", (dir / name).string(), "--out", (dir / "out" / "mesh.ply").string()};
  args.insert(args.end(), extra.begin(), extra.end());
  const Interrupted r = interrupt_run(dir, std::move(args), "", SIGTERM, delay);
  EXPECT_EQ(r.exit_code, 130) << r.err;
  EXPECT_NE(r.err.find("interrupted"), std::string::npos) << r.err;
  ::testing::Test::RecordProperty("seconds_to_stop", std::to_string(r.seconds_to_stop));
  if (kTimingMeaningful) {
    EXPECT_LT(r.seconds_to_stop, limit);
  }
  EXPECT_TRUE(test::file_names(dir / "out").empty()) << "no new, partial or temporary file";
}

TEST(Interrupt, SignalMidCurvedMeshingStopsWithinASecond) {
  // A terrain of 20 000 triangles, one curved surface, remeshed to edges of
  // 0.05 (about 265 000 triangles): CGAL's remeshing of it is one call of
  // seconds, which used to run to its end before the signal was seen
  // (docs/robustness.md, "Interrupted runs"). The input is small and the
  // output large, so the signal lands in the remeshing however fast the
  // coarsening of a fine input has become.
  const auto dir = test::fresh_dir("interrupt_curved");
  constexpr int kSide = 101;
  std::string obj;
  obj.reserve(40u * kSide * kSide);
  char line[96];
  for (int j = 0; j < kSide; ++j) {
    for (int i = 0; i < kSide; ++i) {
      const double x = 10.0 * i / (kSide - 1), z = 10.0 * j / (kSide - 1);
      std::snprintf(line, sizeof line, "v %.5f %.5f %.5f\n", x, 0.3 * std::sin(1.3 * x) * std::cos(0.9 * z), z);
      obj += line;
    }
  }
  for (int j = 0; j + 1 < kSide; ++j) {
    for (int i = 0; i + 1 < kSide; ++i) {
      const int a = j * kSide + i + 1, b = a + 1, c = a + kSide, d = c + 1;
      std::snprintf(line, sizeof line, "f %d %d %d\nf %d %d %d\n", a, c, d, a, d, b);
      obj += line;
    }
  }
  test::write_text(dir / "terrain.obj", obj);
  expect_mesh_stops_within(dir, "terrain.obj", std::chrono::milliseconds(1500), 1.0, {"--max-edge", "0.05"});
}


TEST(Interrupt, SignalMidObjParseStopsWithinHalfASecond) {
  // A lit quad after three million vertex lines (40 MB): the parse alone
  // takes about a second, and the reader calls the checkpoint every few
  // thousand lines (LoadOptions::checkpoint), so a signal need not wait for
  // its end (docs/robustness.md, "Interrupted runs").
  const auto dir = test::fresh_dir("interrupt_obj_parse");
  test::write_text(dir / "big.mtl", "newmtl floor\nKd 0.7 0.6 0.5\nnewmtl light\nKd 0 0 0\nKe 3 3 3\n");
  std::string obj = "mtllib big.mtl\n";
  constexpr int kLines = 3000000;
  obj.reserve(14u * kLines + 256);
  for (int i = 0; i < kLines; ++i) obj += "v 0.5 0.5 0.5\n";
  obj += "usemtl floor\nv 0 0 0\nv 1 0 0\nv 1 0 1\nv 0 0 1\nf -4 -1 -2 -3\n"
         "usemtl light\nv 0.25 1 0.25\nv 0.75 1 0.25\nv 0.75 1 0.75\nv 0.25 1 0.75\nf -4 -3 -2 -1\n";
  test::write_text(dir / "big.obj", obj);
  expect_mesh_stops_within(dir, "big.obj", std::chrono::milliseconds(100), 0.5);
}

}  // namespace
}  // namespace lhr
