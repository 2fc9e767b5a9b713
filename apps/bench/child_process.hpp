#pragma once
// Running a program as a child process and measuring it: wall-clock time and
// peak resident memory, with a way to stop it early (`lhr bench` runs every
// solve in its own process so that its memory is its own).

#include <cstddef>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace lhr {

struct ChildOptions {
  std::filesystem::path log;          // stdout and stderr go here (truncated first); empty: ours
  std::filesystem::path working_dir;  // empty: ours
  // Polled every few milliseconds; once it says true the child gets SIGTERM,
  // and SIGKILL if it has not ended a few seconds later.
  std::function<bool()> stop_requested;
};

struct ChildResult {
  int exit_code = -1;    // -1 when a signal ended it
  int signal = 0;        // the signal that ended it, or 0
  bool stopped = false;  // stop_requested ended it
  double seconds = 0.0;  // wall clock from start to exit
  // The child's ru_maxrss (from wait4). Linux carries the high-water mark
  // of the address space a child execs from into its count, so the parent's
  // own peak is a floor: keep the parent small.
  std::size_t peak_rss_bytes = 0;
};

// Runs program (a path, or a bare name searched on PATH) with args as
// argv[1..], stdin from /dev/null, and waits for it. Throws
// std::runtime_error naming the program when it cannot be started.
ChildResult run_child(const std::filesystem::path& program, const std::vector<std::string>& args,
                      const ChildOptions& options = {});

// The last non-blank line of a log (a child's or a tool's): where programs
// put their error. "no message" for an empty or missing log.
std::string last_log_line(const std::filesystem::path& log);

// The executable a bare name stands for on PATH, if any.
std::optional<std::filesystem::path> find_on_path(const std::string& name);

}  // namespace lhr
