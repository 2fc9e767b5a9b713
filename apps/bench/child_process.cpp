#include "apps/bench/child_process.hpp"

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <stdexcept>
#include <thread>

extern char** environ;

namespace lhr {

namespace {

using Clock = std::chrono::steady_clock;

// Short enough that the wall-clock figure is off by at most this much.
constexpr auto kPollInterval = std::chrono::milliseconds(5);
// A solve stops at its next phase boundary; one stuck longer is killed.
constexpr auto kGracePeriod = std::chrono::seconds(5);

class SpawnActions {
 public:
  SpawnActions() { posix_spawn_file_actions_init(&actions_); }
  ~SpawnActions() { posix_spawn_file_actions_destroy(&actions_); }
  SpawnActions(const SpawnActions&) = delete;
  SpawnActions& operator=(const SpawnActions&) = delete;
  posix_spawn_file_actions_t* get() { return &actions_; }

 private:
  posix_spawn_file_actions_t actions_;
};

}  // namespace

std::optional<std::filesystem::path> find_on_path(const std::string& name) {
  if (name.find('/') != std::string::npos) {
    if (::access(name.c_str(), X_OK) == 0) return std::filesystem::path(name);
    return std::nullopt;
  }
  const char* path = std::getenv("PATH");
  const std::string dirs = path ? path : "/usr/local/bin:/usr/bin:/bin";
  std::size_t start = 0;
  while (start <= dirs.size()) {
    const std::size_t colon = dirs.find(':', start);
    const std::string dir = dirs.substr(start, colon == std::string::npos ? std::string::npos : colon - start);
    const std::filesystem::path candidate = std::filesystem::path(dir.empty() ? "." : dir) / name;
    std::error_code ec;
    if (std::filesystem::is_regular_file(candidate, ec) && ::access(candidate.c_str(), X_OK) == 0) return candidate;
    if (colon == std::string::npos) break;
    start = colon + 1;
  }
  return std::nullopt;
}

ChildResult run_child(const std::filesystem::path& program, const std::vector<std::string>& args,
                      const ChildOptions& options) {
  const std::optional<std::filesystem::path> executable = find_on_path(program.string());
  if (!executable) throw std::runtime_error(program.string() + ": cannot start: no such executable");
  std::vector<std::string> argv_text{program.string()};
  argv_text.insert(argv_text.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (std::string& a : argv_text) argv.push_back(a.data());
  argv.push_back(nullptr);

  SpawnActions actions;
  posix_spawn_file_actions_addopen(actions.get(), STDIN_FILENO, "/dev/null", O_RDONLY, 0);
  if (!options.log.empty()) {
    posix_spawn_file_actions_addopen(actions.get(), STDOUT_FILENO, options.log.c_str(),
                                     O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_adddup2(actions.get(), STDOUT_FILENO, STDERR_FILENO);
  }
  if (!options.working_dir.empty()) posix_spawn_file_actions_addchdir_np(actions.get(), options.working_dir.c_str());

  const auto start = Clock::now();
  pid_t pid = 0;
  const int spawned = posix_spawn(&pid, executable->c_str(), actions.get(), nullptr, argv.data(), environ);
  if (spawned != 0) throw std::runtime_error(program.string() + ": cannot start: " + std::strerror(spawned));

  ChildResult result;
  std::optional<Clock::time_point> terminated_at;
  bool killed = false;
  while (true) {
    int status = 0;
    rusage usage{};
    const pid_t done = ::wait4(pid, &status, WNOHANG, &usage);
    if (done == pid) {
      result.seconds = std::chrono::duration<double>(Clock::now() - start).count();
      result.peak_rss_bytes = static_cast<std::size_t>(usage.ru_maxrss) * 1024;  // Linux reports KiB
      if (WIFEXITED(status)) result.exit_code = WEXITSTATUS(status);
      if (WIFSIGNALED(status)) result.signal = WTERMSIG(status);
      result.stopped = terminated_at.has_value();
      return result;
    }
    if (done < 0 && errno != EINTR) {
      throw std::runtime_error(program.string() + ": cannot wait for it: " + std::strerror(errno));
    }
    if (!terminated_at && options.stop_requested && options.stop_requested()) {
      ::kill(pid, SIGTERM);
      terminated_at = Clock::now();
    } else if (terminated_at && !killed && Clock::now() - *terminated_at > kGracePeriod) {
      ::kill(pid, SIGKILL);
      killed = true;
    }
    std::this_thread::sleep_for(kPollInterval);
  }
}

std::string last_log_line(const std::filesystem::path& log) {
  std::ifstream in(log);
  std::string line, last = "no message";
  while (std::getline(in, line)) {
    if (line.find_first_not_of(" \t\r") != std::string::npos) last = line;
  }
  return last;
}

}  // namespace lhr
