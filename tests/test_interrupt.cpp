// An interrupted `lhr solve` or `lhr reference`, of an image or at a mesh's
// vertices (SIGINT or SIGTERM mid-run)
// exits cleanly with code 130, writes no file, and leaves an existing output
// untouched.

#include <gtest/gtest.h>
#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <thread>

#include "test_support.hpp"

extern char** environ;

namespace lhr {
namespace {

struct Interrupted {
  int exit_code = -1;
  std::string err;
};

// Starts `lhr` with args (a run of many seconds) and signals it `delay`
// after `marker` appears on its stderr: the run is then mid-work.
Interrupted interrupt_run(const std::filesystem::path& dir, std::vector<std::string> args, const std::string& marker,
                          int signal, std::chrono::milliseconds delay) {
  const std::string err_file = (dir / "stderr.txt").string();
  args.insert(args.begin(), LHR_EXECUTABLE);
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, err_file.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  pid_t pid = 0;
  const int spawned = posix_spawn(&pid, argv[0], &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  Interrupted result;
  if (spawned != 0) return result;
  for (int waited = 0; waited < 600; ++waited) {
    if (test::read_text(err_file).find(marker) != std::string::npos) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  std::this_thread::sleep_for(delay);
  kill(pid, signal);
  int status = 0;
  waitpid(pid, &status, 0);
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
    std::vector<std::string> files;
    for (const auto& entry : std::filesystem::directory_iterator(dir / "out")) {
      files.push_back(entry.path().filename().string());
    }
    EXPECT_EQ(files, std::vector<std::string>{"mesh.ply"}) << "no new, partial or temporary file";
  }
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
    std::vector<std::string> files;
    for (const auto& entry : std::filesystem::directory_iterator(dir / "out")) {
      files.push_back(entry.path().filename().string());
    }
    EXPECT_EQ(files, std::vector<std::string>{"ref.exr"}) << "no new, partial or temporary file";
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
  std::vector<std::string> files;
  for (const auto& entry : std::filesystem::directory_iterator(dir / "out")) {
    files.push_back(entry.path().filename().string());
  }
  EXPECT_EQ(files, std::vector<std::string>{"ref.ply"}) << "no new, partial or temporary file";
}

}  // namespace
}  // namespace lhr
