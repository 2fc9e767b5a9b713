// Nothing is lost on a failed write: a full disk (injected, and a real one on
// a small tmpfs where the test may mount it), an unwritable output location
// and concurrent solves into one directory each leave the earlier outputs
// byte-identical, no temporary file, and one line with the OS's reason.

#include <gtest/gtest.h>
#include <fcntl.h>
#include <sys/mount.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstring>
#include <functional>
#include <iostream>
#include <map>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "io/atomic_file.hpp"
#include "io/image_io.hpp"
#include "io/json_file.hpp"
#include "io/mesh_io.hpp"
#include "io/output_dir.hpp"
#include "test_support.hpp"


namespace lhr {
namespace {

const std::string kEarlier = "earlier result\n";

std::vector<std::string> files_in(const std::filesystem::path& dir) {
  std::vector<std::string> names;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) names.push_back(entry.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

std::string no_space_message() { return std::strerror(ENOSPC); }

// A 10 x 10 grid of unit squares, two triangles each, radiance varying over it.
ExportMesh grid_mesh() {
  ExportMesh m;
  constexpr int kN = 10;
  for (int j = 0; j <= kN; ++j) {
    for (int i = 0; i <= kN; ++i) {
      m.points.emplace_back(i, j, 0.0);
      m.colours.push_back({static_cast<std::uint8_t>(20 * i), static_cast<std::uint8_t>(20 * j), 7});
      m.radiance.emplace_back(0.1 * i, 0.1 * j, 0.5);
    }
  }
  const auto at = [](int i, int j) { return j * (kN + 1) + i; };
  for (int j = 0; j < kN; ++j) {
    for (int i = 0; i < kN; ++i) {
      m.triangles.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
      m.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
    }
  }
  return m;
}

Image gradient_image() {
  Image image(32, 24);
  for (std::size_t k = 0; k < image.rgb.size(); ++k) image.rgb[k] = static_cast<float>(k % 97) / 97.0f;
  return image;
}

using Writer = std::function<void(const std::filesystem::path&)>;

struct Format {
  std::string file;
  Writer write;
};

std::vector<Format> every_format() {
  const ExportMesh mesh = grid_mesh();
  const Image image = gradient_image();
  nlohmann::json doc;
  doc["links"] = 12345;
  doc["values"] = std::vector<double>(200, 0.25);
  return {
      {"mesh.ply", [mesh](const std::filesystem::path& p) { write_mesh(p, mesh); }},
      {"mesh.off", [mesh](const std::filesystem::path& p) { write_mesh(p, mesh); }},
      {"image.png", [image](const std::filesystem::path& p) { write_image(p, image); }},
      {"image.exr", [image](const std::filesystem::path& p) { write_image(p, image); }},
      {"stats.json", [doc](const std::filesystem::path& p) { write_json_file(p, doc); }},
  };
}

TEST(SafeWrites, InjectedFullDiskAtAnyByteKeepsTheEarlierFile) {
  for (const Format& format : every_format()) {
    SCOPED_TRACE(format.file);
    const auto dir = test::fresh_dir("safe_writes_injected");
    const auto complete = dir / ("complete_" + format.file);
    format.write(complete);
    const std::uintmax_t size = std::filesystem::file_size(complete);
    ASSERT_GT(size, 100u);
    const auto target = dir / format.file;
    // Failing at the first, second, middle and last byte: each is caught.
    for (const std::uintmax_t fail_after : {std::uintmax_t{0}, std::uintmax_t{1}, size / 2, size - 1}) {
      SCOPED_TRACE(fail_after);
      test::write_text(target, kEarlier);
      std::string message;
      {
        const InjectedWriteFailure full_disk(fail_after, ENOSPC);
        try {
          format.write(target);
        } catch (const std::runtime_error& e) {
          message = e.what();
        }
      }
      EXPECT_NE(message.find(target.string()), std::string::npos) << message;
      EXPECT_NE(message.find(no_space_message()), std::string::npos) << message;
      EXPECT_EQ(test::count_lines(message), 1) << message;
      EXPECT_EQ(test::read_text(target), kEarlier);
      std::vector<std::string> only_these{"complete_" + format.file, format.file};
      std::sort(only_these.begin(), only_these.end());
      EXPECT_EQ(files_in(dir), only_these)
          << "no temporary file left";
    }
    // Exactly enough room: written whole.
    {
      const InjectedWriteFailure just_enough(size, ENOSPC);
      EXPECT_NO_THROW(format.write(target));
    }
    EXPECT_EQ(std::filesystem::file_size(target), size);
  }
}

TEST(SafeWrites, AFailureInASetLeavesEveryEarlierOutputOfTheSet) {
  const auto dir = test::fresh_dir("safe_writes_set");
  const std::string hundred(100, 'x');
  for (const char* name : {"a.txt", "b.txt", "c.txt"}) test::write_text(dir / name, kEarlier);
  std::string message;
  try {
    // The first two fit; the third does not.
    const InjectedWriteFailure full_disk(250, ENOSPC);
    AtomicOutputs outputs;
    for (const char* name : {"a.txt", "b.txt", "c.txt"}) {
      outputs.stage(dir / name, [&](std::ostream& out) { out << hundred; });
    }
    outputs.publish();
  } catch (const std::runtime_error& e) {
    message = e.what();
  }
  EXPECT_NE(message.find((dir / "c.txt").string()), std::string::npos) << message;
  EXPECT_NE(message.find(no_space_message()), std::string::npos) << message;
  for (const char* name : {"a.txt", "b.txt", "c.txt"}) EXPECT_EQ(test::read_text(dir / name), kEarlier) << name;
  EXPECT_EQ(files_in(dir), (std::vector<std::string>{"a.txt", "b.txt", "c.txt"}));
}

TEST(SafeWrites, ASetAbandonedBeforePublishingRemovesItsTemporaries) {
  const auto dir = test::fresh_dir("safe_writes_abandoned");
  test::write_text(dir / "a.txt", kEarlier);
  {
    AtomicOutputs outputs;
    outputs.stage(dir / "a.txt", [](std::ostream& out) { out << "new"; });
    outputs.stage(dir / "b.txt", [](std::ostream& out) { out << "new"; });
    EXPECT_EQ(files_in(dir).size(), 3u) << "two temporaries beside a.txt while staged";
  }
  EXPECT_EQ(test::read_text(dir / "a.txt"), kEarlier);
  EXPECT_EQ(files_in(dir), std::vector<std::string>{"a.txt"});
}

TEST(SafeWrites, UnwritableDirectoriesAreFoundWithTheOsReason) {
  const auto dir = test::fresh_dir("safe_writes_unwritable");
  EXPECT_NO_THROW(check_output_directory(dir));
  EXPECT_EQ(files_in(dir), std::vector<std::string>{}) << "the probe is removed";
  const auto expect_refused = [](const std::filesystem::path& d, const std::string& problem, bool with_reason) {
    try {
      check_output_directory(d);
      ADD_FAILURE() << d << " accepted";
    } catch (const std::runtime_error& e) {
      const std::string message = e.what();
      EXPECT_EQ(message.rfind(d.string() + ": " + problem, 0), 0u) << message;
      if (with_reason) {
        EXPECT_GT(message.size(), d.string().size() + problem.size()) << "no reason: " << message;
      }
    }
  };
  // /proc/self is a directory but no file can be made in it.
  expect_refused("/proc/self", "cannot write here: ", true);
  expect_refused(dir / "missing", "output directory does not exist", false);
  test::write_text(dir / "file", "x");
  expect_refused(dir / "file", "is not a directory", false);
}

TEST(SafeWrites, EveryWritingCommandRefusesAnUnwritableOutBeforeItsWork) {
  const auto dir = test::fresh_dir("safe_writes_commands");
  test::write_lit_floor_obj(dir);
  const std::string scene = (dir / "tiny.obj").string();
  const std::vector<std::vector<std::string>> commands = {
      {"solve", scene, "--out", "/proc/self", "--verbose"},
      {"solve", scene, "--out", "/proc/self/new_dir"},
      {"mesh", scene, "--out", "/proc/self/mesh.ply"},
      {"reference", scene, "--spp", "2", "--out", "/proc/self/ref.exr", "--verbose"},
      {"scene", "two-rooms", "--out-dir", "/proc/self"},
  };
  for (const auto& args : commands) {
    SCOPED_TRACE(args[0] + " " + args[args.size() - 1]);
    const test::CommandResult r = test::run_lhr(args);
    EXPECT_EQ(r.exit_code, 1) << r.err;
    EXPECT_EQ(test::count_lines(r.err), 1) << r.err;
    EXPECT_NE(r.err.find("/proc/self"), std::string::npos) << r.err;
    EXPECT_EQ(r.err.find("iteration"), std::string::npos) << "found before solving: " << r.err;
    EXPECT_EQ(r.err.find("rendering"), std::string::npos) << "found before rendering: " << r.err;
  }
}

TEST(SafeWrites, AnOutputNameOfUnknownFormatIsRefusedBeforeTheInputIsRead) {
  // The scene does not exist: an error naming it would mean the command read
  // (and, for a real scene, meshed) its input before looking at --out.
  const auto dir = test::fresh_dir("safe_writes_formats");
  const std::string missing = (dir / "missing.obj").string();
  const std::vector<std::vector<std::string>> commands = {
      {"mesh", missing, "--out", (dir / "mesh").string()},
      {"mesh", missing, "--out", (dir / "mesh.obj").string()},
      {"reference", missing, "--spp", "2", "--out", (dir / "ref.png").string()},
  };
  for (const auto& args : commands) {
    SCOPED_TRACE(args[0] + " " + args.back());
    const test::CommandResult r = test::run_lhr(args);
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_NE(r.err.find("--out must name a"), std::string::npos) << r.err;
    EXPECT_EQ(r.err.find("missing.obj"), std::string::npos) << r.err;
  }
  // A name in capitals is still the format it names.
  const test::CommandResult upper = test::run_lhr({"mesh", missing, "--out", (dir / "MESH.PLY").string()});
  EXPECT_EQ(upper.exit_code, 1) << upper.err;
  EXPECT_NE(upper.err.find("missing.obj"), std::string::npos) << upper.err;
}

TEST(SafeWrites, ASecondHolderOfAnOutputDirectoryIsRefused) {
  const auto dir = test::fresh_dir("safe_writes_lock");
  test::write_lit_floor_obj(dir);
  std::filesystem::create_directories(dir / "out");
  test::write_text(dir / "out" / "mesh.ply", kEarlier);
  {
    const OutputDirectoryLock held(dir / "out");
    EXPECT_THROW(OutputDirectoryLock(dir / "out"), std::runtime_error);
    const test::CommandResult r = test::run_lhr({"solve", (dir / "tiny.obj").string(), "--out", (dir / "out").string()});
    EXPECT_EQ(r.exit_code, 1) << r.err;
    EXPECT_EQ(test::count_lines(r.err), 1) << r.err;
    EXPECT_NE(r.err.find("another lhr solve is writing to this directory"), std::string::npos) << r.err;
    EXPECT_EQ(test::read_text(dir / "out" / "mesh.ply"), kEarlier);
    EXPECT_EQ(files_in(dir / "out"), std::vector<std::string>{"mesh.ply"});
  }
  EXPECT_NO_THROW(OutputDirectoryLock(dir / "out"));
  const test::CommandResult r = test::run_lhr({"solve", (dir / "tiny.obj").string(), "--out", (dir / "out").string()});
  EXPECT_EQ(r.exit_code, 0) << r.err;
}

// What identifies a solve's output set: the bytes of the meshes and the PNG,
// the EXR's pixels (its header carries the time of writing), and stats.json
// without its timings.
struct OutputSet {
  std::string ply, off, png;
  std::vector<float> exr;
  nlohmann::json stats;
  bool operator==(const OutputSet&) const = default;
};

OutputSet read_set(const std::filesystem::path& dir) {
  OutputSet s;
  s.ply = test::read_text(dir / "mesh.ply");
  s.off = test::read_text(dir / "mesh.off");
  s.png = test::read_text(dir / "image.png");
  s.exr = read_image(dir / "image.exr").rgb;
  s.stats = nlohmann::json::parse(test::read_text(dir / "stats.json"));
  s.stats.erase("seconds");
  s.stats.erase("peak_memory_mib");
  return s;
}

int exit_code_of(pid_t pid) {
  int status = 0;
  if (waitpid(pid, &status, 0) != pid) return -1;
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

TEST(SafeWrites, ConcurrentSolvesIntoOneDirectoryLeaveOneRunsSet) {
  const auto dir = test::fresh_dir("safe_writes_concurrent");
  test::write_lit_floor_obj(dir);
  const std::string scene = (dir / "tiny.obj").string();
  // Two runs whose every output differs: the finer one has more elements.
  const std::array<std::vector<std::string>, 2> flags = {std::vector<std::string>{"--eps-pixel", "0.3"},
                                                         std::vector<std::string>{"--eps-pixel", "0.1"}};
  std::array<OutputSet, 2> expected;
  for (int k = 0; k < 2; ++k) {
    const auto alone = dir / ("alone" + std::to_string(k));
    std::vector<std::string> args{"solve", scene, "--out", alone.string(), "--quiet"};
    args.insert(args.end(), flags[k].begin(), flags[k].end());
    ASSERT_EQ(test::run_lhr(args).exit_code, 0);
    expected[k] = read_set(alone);
  }
  ASSERT_NE(expected[0].ply, expected[1].ply);
  ASSERT_NE(expected[0].stats, expected[1].stats);

  const auto shared = dir / "shared";
  int refused = 0;
  for (int trial = 0; trial < 3; ++trial) {
    SCOPED_TRACE(trial);
    std::array<pid_t, 2> pids{};
    for (int k = 0; k < 2; ++k) {
      std::vector<std::string> args{"solve", scene, "--out", shared.string(), "--quiet"};
      args.insert(args.end(), flags[k].begin(), flags[k].end());
      pids[k] = test::spawn_lhr(args, dir / ("err" + std::to_string(k)));
      ASSERT_GT(pids[k], 0);
    }
    int succeeded = 0;
    for (int k = 0; k < 2; ++k) {
      const int code = exit_code_of(pids[k]);
      const std::string err = test::read_text(dir / ("err" + std::to_string(k)));
      if (code == 0) {
        ++succeeded;
      } else {
        ++refused;
        EXPECT_EQ(code, 1) << err;
        EXPECT_NE(err.find("another lhr solve is writing to this directory"), std::string::npos) << err;
        EXPECT_EQ(test::count_lines(err), 1) << err;
      }
    }
    EXPECT_GE(succeeded, 1);
    const OutputSet found = read_set(shared);
    EXPECT_TRUE(found == expected[0] || found == expected[1]) << "a mixed set after trial " << trial;
    EXPECT_EQ(files_in(shared),
              (std::vector<std::string>{"image.exr", "image.png", "mesh.off", "mesh.ply", "stats.json"}));
  }
  std::cout << "[ info ] " << refused << " of 6 solves found the directory held\n";
}

// A real full filesystem: a 1 MiB tmpfs mounted for the test (the test runs
// as root in CI; elsewhere it is skipped).
class SafeWritesOnTmpfs : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = test::fresh_dir("safe_writes_tmpfs");
    mount_ = dir_ / "mnt";
    std::filesystem::create_directories(mount_);
    if (::mount("tmpfs", mount_.c_str(), "tmpfs", 0, "size=1m") != 0) {
      GTEST_SKIP() << "cannot mount a tmpfs here (" << std::strerror(errno) << "); needs root";
    }
    mounted_ = true;
    test::write_lit_floor_obj(dir_);
    scene_ = (dir_ / "tiny.obj").string();
  }
  void TearDown() override {
    if (mounted_) ::umount2(mount_.c_str(), MNT_DETACH);
  }

  // Writes a filler file until the filesystem is full, then gives back
  // `leave` bytes.
  void fill(std::size_t leave) {
    const auto filler = mount_ / "filler";
    const int fd = ::open(filler.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    ASSERT_GE(fd, 0);
    const std::vector<char> block(4096, 'f');
    off_t size = 0;
    for (;;) {
      const ssize_t n = ::write(fd, block.data(), block.size());
      if (n <= 0) break;
      size += n;
    }
    ASSERT_EQ(errno, ENOSPC);
    ASSERT_EQ(::ftruncate(fd, std::max<off_t>(0, size - static_cast<off_t>(leave))), 0);
    ::close(fd);
  }

  std::map<std::string, std::string> contents(const std::filesystem::path& d) {
    std::map<std::string, std::string> m;
    for (const std::string& name : files_in(d)) m[name] = test::read_text(d / name);
    return m;
  }

  std::filesystem::path dir_, mount_;
  std::string scene_;
  bool mounted_ = false;
};

TEST_F(SafeWritesOnTmpfs, AFullDiskMidOutputKeepsTheEarlierSolveAndSaysWhy) {
  const auto out = mount_ / "out";
  ASSERT_EQ(test::run_lhr({"solve", scene_, "--out", out.string(), "--quiet"}).exit_code, 0);
  const auto earlier = contents(out);
  ASSERT_EQ(earlier.size(), 5u);
  // Room for the probe and part of a mesh, not for the finer run's outputs.
  fill(48 * 1024);
  const test::CommandResult r =
      test::run_lhr({"solve", scene_, "--out", out.string(), "--eps-pixel", "0.1", "--quiet"});
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_EQ(test::count_lines(r.err), 1) << r.err;
  EXPECT_NE(r.err.find(no_space_message()), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(out.string()), std::string::npos) << r.err;
  EXPECT_TRUE(contents(out) == earlier) << "the earlier set, byte for byte, and no temporary";
}

TEST_F(SafeWritesOnTmpfs, AFullDiskMidMeshKeepsTheEarlierMesh) {
  const auto out = mount_ / "initial.ply";
  ASSERT_EQ(test::run_lhr({"mesh", scene_, "--out", out.string(), "--quiet"}).exit_code, 0);
  const std::string earlier = test::read_text(out);
  fill(48 * 1024);
  // h = 0.01: about 1.8 MB of PLY.
  const test::CommandResult r =
      test::run_lhr({"mesh", scene_, "--out", out.string(), "--max-edge", "0.01", "--quiet"});
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_EQ(test::count_lines(r.err), 1) << r.err;
  EXPECT_NE(r.err.find(no_space_message()), std::string::npos) << r.err;
  EXPECT_EQ(test::read_text(out), earlier);
  EXPECT_EQ(files_in(mount_), (std::vector<std::string>{"filler", "initial.ply"}));
}

TEST_F(SafeWritesOnTmpfs, AFullOrReadOnlyDiskIsFoundBeforeTheSolve) {
  const auto out = mount_ / "out";
  std::filesystem::create_directories(out);
  fill(0);
  test::CommandResult r = test::run_lhr({"solve", scene_, "--out", out.string(), "--verbose"});
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find(out.string() + ": cannot write here: " + no_space_message()), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("iteration"), std::string::npos) << r.err;
  EXPECT_EQ(files_in(out), std::vector<std::string>{});

  std::filesystem::remove(mount_ / "filler");
  ASSERT_EQ(::mount("tmpfs", mount_.c_str(), "tmpfs", MS_REMOUNT | MS_RDONLY, "size=1m"), 0) << std::strerror(errno);
  r = test::run_lhr({"solve", scene_, "--out", out.string(), "--verbose"});
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find(out.string() + ": cannot write here: " + std::strerror(EROFS)), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("iteration"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace lhr
