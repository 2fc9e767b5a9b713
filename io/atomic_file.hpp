#pragma once
// Outputs are written to a temporary name beside the target, synced to disk
// and renamed, so a failure (a full disk, an I/O error, a signal) never leaves
// a half-written file or destroys an existing one (docs/robustness.md).

#include <cstdint>
#include <filesystem>
#include <functional>
#include <ostream>
#include <vector>

namespace lhr {

// A set of outputs published together: stage() writes each one completely to
// a temporary beside its target and fsyncs it; publish() renames them all
// into place, in staging order, and fsyncs their directories. Destroyed
// before publish() (an exception, an interrupt), it removes every temporary,
// so the earlier outputs stay as they were, all of them: a failure on the
// last file does not leave the first ones replaced.
class AtomicOutputs {
 public:
  AtomicOutputs() = default;
  AtomicOutputs(const AtomicOutputs&) = delete;
  AtomicOutputs& operator=(const AtomicOutputs&) = delete;
  ~AtomicOutputs();

  // write() fills a binary stream; every write, the flush, fsync and close
  // are checked. Throws std::runtime_error "TARGET: cannot write: REASON"
  // with the OS's reason (strerror), after removing the temporary.
  void stage(const std::filesystem::path& target, const std::function<void(std::ostream& out)>& write);

  // For writers that only take a file name: write(temp_path) creates the
  // file, which is then fsync'd. Their own write errors are theirs to report.
  void stage_by_path(const std::filesystem::path& target,
                     const std::function<void(const std::filesystem::path& temp_path)>& write);

  // Renames every staged file to its target. Throws if a rename or the
  // directory sync fails (the files renamed before it stay published).
  void publish();

 private:
  struct Staged {
    std::filesystem::path target;
    std::filesystem::path temp;
  };
  std::vector<Staged> staged_;
};

// One output through a stream: AtomicOutputs with one file.
void write_stream_atomically(const std::filesystem::path& target,
                             const std::function<void(std::ostream& out)>& write);

// One output through a writer that takes a file name.
void write_atomically(const std::filesystem::path& target,
                      const std::function<void(const std::filesystem::path& temp_path)>& write);

// Test seam: while an instance lives, output data past the first
// `after_bytes` bytes (counted over every file staged in the process) fails to
// write with `error_number` (ENOSPC: the disk is full), as write(2) would.
// Lets tests reach every failure path without a full filesystem.
class InjectedWriteFailure {
 public:
  InjectedWriteFailure(std::uintmax_t after_bytes, int error_number);
  InjectedWriteFailure(const InjectedWriteFailure&) = delete;
  InjectedWriteFailure& operator=(const InjectedWriteFailure&) = delete;
  ~InjectedWriteFailure();
};

}  // namespace lhr
