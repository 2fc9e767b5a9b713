#include "test_support.hpp"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cstdlib>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <stdexcept>

extern char** environ;

namespace lhr::test {

namespace {

std::string shell_quote(const std::string& s) {
  std::string q = "'";
  for (char c : s) {
    if (c == '\'') q += "'\\''";
    else q += c;
  }
  return q + "'";
}

}  // namespace

CommandResult run_lhr(const std::vector<std::string>& args) {
  const std::filesystem::path dir = fresh_dir("run_lhr_capture");
  const auto out_file = dir / "stdout";
  const auto err_file = dir / "stderr";
  std::ostringstream command;
  command << shell_quote(LHR_EXECUTABLE);
  for (const std::string& a : args) command << ' ' << shell_quote(a);
  command << " </dev/null >" << shell_quote(out_file.string()) << " 2>" << shell_quote(err_file.string());
  const int status = std::system(command.str().c_str());
  CommandResult r;
  // The shell reports a child killed by signal N as exit status 128+N.
  if (status != -1 && WIFEXITED(status) && WEXITSTATUS(status) < 128) r.exit_code = WEXITSTATUS(status);
  r.out = read_text(out_file);
  r.err = read_text(err_file);
  return r;
}

std::filesystem::path source_dir() { return LHR_SOURCE_DIR; }

namespace {

// Every test process keeps its scratch files under one directory named after
// its pid, removed when the process exits (LHR_KEEP_TEST_DIRS=1 keeps it for a
// post-mortem). A forked child that exits normally must not remove its
// parent's directory, hence the pid check.
class ScratchRoot {
 public:
  const std::filesystem::path& path() {
    if (path_.empty()) {
      owner_ = ::getpid();
      path_ = std::filesystem::temp_directory_path() / ("lhr-test-" + std::to_string(owner_));
    }
    return path_;
  }
  ~ScratchRoot() {
    if (path_.empty() || ::getpid() != owner_ || std::getenv("LHR_KEEP_TEST_DIRS")) return;
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
  }

 private:
  std::filesystem::path path_;
  pid_t owner_ = 0;
};

ScratchRoot scratch_root;

}  // namespace

std::filesystem::path fresh_dir(const std::string& name) {
  const auto dir = scratch_root.path() / name;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

void write_text(const std::filesystem::path& path, const std::string& text) {
  std::ofstream f(path, std::ios::binary);
  f << text;
  if (!f) throw std::runtime_error("cannot write " + path.string());
}

std::filesystem::path fresh_file(const std::string& dir_name, const std::string& file_name, const std::string& text) {
  const auto path = fresh_dir(dir_name) / file_name;
  write_text(path, text);
  return path;
}

std::string read_text(const std::filesystem::path& path) {
  std::ifstream f(path, std::ios::binary);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

int count_lines(const std::string& text) {
  int n = 0;
  for (char c : text) n += (c == '\n');
  if (!text.empty() && text.back() != '\n') ++n;
  return n;
}

std::vector<std::string> containing(const std::vector<std::string>& texts, const std::string& fragment) {
  std::vector<std::string> out;
  for (const std::string& t : texts) {
    if (t.find(fragment) != std::string::npos) out.push_back(t);
  }
  return out;
}

void write_lit_floor_obj(const std::filesystem::path& dir) {
  write_text(dir / "tiny.mtl", "newmtl floor\nKd 0.7 0.6 0.5\nKe 0 0 0\n"
                               "newmtl light\nKd 0 0 0\nKe 3 3 3\n");
  write_text(dir / "tiny.obj",
             "mtllib tiny.mtl\n"
             "g floor\nusemtl floor\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n"
             "g light\nusemtl light\nv 0.2 0.2 0.5\nv 0.2 0.8 0.5\nv 0.8 0.8 0.5\nv 0.8 0.2 0.5\nf 5 6 7 8\n");
}

void write_glowing_cube(const std::filesystem::path& dir) {
  write_text(dir / "cube.mtl", "newmtl glow\nKd 0.5 0.5 0.5\nKe 1 1 1\n");
  write_text(dir / "cube.obj",
             "mtllib cube.mtl\n"
             "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
             "usemtl glow\nf 1 2 3 4\nf 5 8 7 6\nf 1 5 6 2\nf 2 6 7 3\nf 3 7 8 4\nf 4 8 5 1\n");
}

pid_t spawn_lhr(std::vector<std::string> args, const std::filesystem::path& err_file) {
  args.insert(args.begin(), LHR_EXECUTABLE);
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, err_file.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  pid_t pid = -1;
  if (posix_spawn(&pid, argv[0], &actions, nullptr, argv.data(), environ) != 0) pid = -1;
  posix_spawn_file_actions_destroy(&actions);
  return pid;
}

std::vector<std::string> file_names(const std::filesystem::path& dir) {
  std::vector<std::string> names;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) names.push_back(entry.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

}  // namespace lhr::test
