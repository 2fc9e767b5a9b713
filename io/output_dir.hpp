#pragma once
// Output locations checked before the work, and an output directory held by
// one `lhr solve` at a time (docs/robustness.md, "Safe writes").

#include <filesystem>

namespace lhr {

// Throws std::runtime_error "DIR: cannot write here: REASON" unless a file
// can be created and written in dir (which must exist). It creates, writes
// and removes a probe file: permission bits miss read-only mounts,
// pseudo-filesystems (/proc, /sys) and a disk with no space left.
void check_output_directory(const std::filesystem::path& dir);

// Creates dir and its parents when missing, then check_output_directory.
void prepare_output_directory(const std::filesystem::path& dir);

// The directory an output file will be written to (its parent, or ".").
void check_output_file_location(const std::filesystem::path& file);

// An exclusive flock(2) on the directory itself, held for the object's
// lifetime: a second holder (another process, or another open in this one)
// is refused at once with a one-line error naming the directory. Locking the
// directory rather than a file in it leaves nothing behind, even after a
// crash: the kernel drops the lock with the process.
class OutputDirectoryLock {
 public:
  explicit OutputDirectoryLock(const std::filesystem::path& dir);
  OutputDirectoryLock(const OutputDirectoryLock&) = delete;
  OutputDirectoryLock& operator=(const OutputDirectoryLock&) = delete;
  ~OutputDirectoryLock();

 private:
  int fd_ = -1;
};

}  // namespace lhr
