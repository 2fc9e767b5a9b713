#include "io/atomic_file.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <mutex>
#include <random>
#include <set>
#include <stdexcept>
#include <streambuf>
#include <string>
#include <system_error>

namespace lhr {

namespace {

struct Injection {
  std::mutex mutex;
  bool active = false;
  std::uintmax_t bytes_left = 0;
  int error_number = 0;
};

Injection& injection() {
  static Injection instance;
  return instance;
}

// How many of `wanted` bytes may be written before the injected failure;
// sets *error when fewer than all.
std::size_t injected_allowance(std::size_t wanted, int* error) {
  Injection& inj = injection();
  const std::lock_guard lock(inj.mutex);
  if (!inj.active) return wanted;
  const auto allowed = static_cast<std::size_t>(std::min<std::uintmax_t>(wanted, inj.bytes_left));
  inj.bytes_left -= allowed;
  if (allowed < wanted) *error = inj.error_number;
  return allowed;
}

[[noreturn]] void fail(const std::filesystem::path& target, const std::string& what, int error_number) {
  throw std::runtime_error(target.string() + ": " + what + ": " + std::strerror(error_number));
}

std::filesystem::path directory_of(const std::filesystem::path& target) {
  return target.has_parent_path() ? target.parent_path() : std::filesystem::path(".");
}

class Descriptor {
 public:
  explicit Descriptor(int fd) : fd_(fd) {}
  Descriptor(const Descriptor&) = delete;
  Descriptor& operator=(const Descriptor&) = delete;
  ~Descriptor() {
    if (fd_ >= 0) ::close(fd_);
  }
  int get() const { return fd_; }
  // close(2)'s result: on NFS and some other filesystems a write error is
  // only reported here.
  int close() {
    const int r = ::close(fd_);
    fd_ = -1;
    return r == 0 ? 0 : errno;
  }

 private:
  int fd_;
};

// A stream buffer over a file descriptor that keeps the first OS error, so a
// failed write is reported with its reason instead of as a short file.
class FileSink : public std::streambuf {
 public:
  explicit FileSink(int fd) : fd_(fd), buffer_(kBufferSize) { setp(buffer_.data(), buffer_.data() + buffer_.size()); }
  int error() const { return error_; }

 protected:
  int_type overflow(int_type ch) override {
    if (!drain()) return traits_type::eof();
    if (!traits_type::eq_int_type(ch, traits_type::eof())) {
      *pptr() = traits_type::to_char_type(ch);
      pbump(1);
    }
    return traits_type::not_eof(ch);
  }
  int sync() override { return drain() ? 0 : -1; }

 private:
  static constexpr std::size_t kBufferSize = 1 << 16;

  bool drain() {
    if (error_ != 0) return false;
    const char* data = pbase();
    std::size_t left = static_cast<std::size_t>(pptr() - pbase());
    while (left > 0) {
      int injected = 0;
      const std::size_t allowed = injected_allowance(left, &injected);
      const ssize_t written = allowed > 0 ? ::write(fd_, data, allowed) : 0;
      if (written < 0) {
        if (errno == EINTR) continue;
        error_ = errno;
        return false;
      }
      data += written;
      left -= static_cast<std::size_t>(written);
      if (injected != 0 && static_cast<std::size_t>(written) == allowed) {
        error_ = injected;
        return false;
      }
    }
    setp(buffer_.data(), buffer_.data() + buffer_.size());
    return true;
  }

  int fd_;
  int error_ = 0;
  std::vector<char> buffer_;
};

// Keep the extension last: OpenMesh and OpenImageIO pick the format from it.
std::filesystem::path temporary_name(const std::filesystem::path& target, unsigned tag) {
  std::string name = ".";
  name.append(target.stem().string())
      .append(".tmp-")
      .append(std::to_string(::getpid()))
      .append("-")
      .append(std::to_string(tag % 1000000))
      .append(target.extension().string());
  std::filesystem::path temp = target;
  temp.replace_filename(name);
  return temp;
}

// Creates the temporary exclusively (O_EXCL), so two processes never share one.
std::filesystem::path create_temporary(const std::filesystem::path& target, int* fd) {
  const std::filesystem::path dir = directory_of(target);
  std::error_code ec;
  if (!std::filesystem::is_directory(dir, ec)) {
    throw std::runtime_error(target.string() + ": output directory does not exist");
  }
  std::random_device rd;
  for (int attempt = 0;; ++attempt) {
    const std::filesystem::path temp = temporary_name(target, rd());
    *fd = ::open(temp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (*fd >= 0) return temp;
    if (errno != EEXIST || attempt > 100) fail(target, "cannot create a file in " + dir.string(), errno);
  }
}

void sync_directory(const std::filesystem::path& dir) {
  Descriptor fd(::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC));
  if (fd.get() < 0) fail(dir, "cannot open the directory to sync it", errno);
  // Some filesystems cannot sync a directory (EINVAL); the rename is then as
  // durable as they make it.
  if (::fsync(fd.get()) != 0 && errno != EINVAL) fail(dir, "cannot sync the directory", errno);
}

}  // namespace

AtomicOutputs::~AtomicOutputs() {
  for (const Staged& s : staged_) {
    std::error_code ignored;
    std::filesystem::remove(s.temp, ignored);
  }
}

void AtomicOutputs::stage(const std::filesystem::path& target, const std::function<void(std::ostream&)>& write) {
  int raw_fd = -1;
  const std::filesystem::path temp = create_temporary(target, &raw_fd);
  staged_.push_back({target, temp});
  try {
    Descriptor fd(raw_fd);
    FileSink sink(fd.get());
    std::ostream out(&sink);
    try {
      write(out);
    } catch (...) {
      // The OS's reason explains a writer's own "cannot write" best.
      if (sink.error() != 0) fail(target, "cannot write", sink.error());
      throw;
    }
    out.flush();
    if (sink.error() != 0) fail(target, "cannot write", sink.error());
    if (!out) throw std::runtime_error(target.string() + ": cannot write: the writer reported a stream failure");
    // The data must be on disk before the rename makes it the output: after a
    // crash the target is then the old file or the complete new one.
    if (::fsync(fd.get()) != 0) fail(target, "cannot write", errno);
    if (const int e = fd.close(); e != 0) fail(target, "cannot write", e);
  } catch (...) {
    std::error_code ignored;
    std::filesystem::remove(temp, ignored);
    staged_.pop_back();
    throw;
  }
}

void AtomicOutputs::stage_by_path(const std::filesystem::path& target,
                                  const std::function<void(const std::filesystem::path&)>& write) {
  int raw_fd = -1;
  const std::filesystem::path temp = create_temporary(target, &raw_fd);
  ::close(raw_fd);
  staged_.push_back({target, temp});
  try {
    write(temp);
    Descriptor fd(::open(temp.c_str(), O_RDONLY | O_CLOEXEC));
    if (fd.get() < 0) fail(target, "cannot write", errno);
    std::error_code ec;
    const std::uintmax_t size = std::filesystem::file_size(temp, ec);
    if (ec) fail(target, "cannot write", ec.value());
    int injected = 0;
    if (injected_allowance(static_cast<std::size_t>(size), &injected) < size) fail(target, "cannot write", injected);
    if (::fsync(fd.get()) != 0) fail(target, "cannot write", errno);
  } catch (...) {
    std::error_code ignored;
    std::filesystem::remove(temp, ignored);
    staged_.pop_back();
    throw;
  }
}

void AtomicOutputs::publish() {
  std::set<std::filesystem::path> dirs;
  while (!staged_.empty()) {
    const Staged s = staged_.front();
    if (::rename(s.temp.c_str(), s.target.c_str()) != 0) fail(s.target, "cannot rename the temporary file", errno);
    staged_.erase(staged_.begin());
    dirs.insert(directory_of(s.target));
  }
  for (const auto& dir : dirs) sync_directory(dir);
}

void write_stream_atomically(const std::filesystem::path& target, const std::function<void(std::ostream&)>& write) {
  AtomicOutputs outputs;
  outputs.stage(target, write);
  outputs.publish();
}

void write_atomically(const std::filesystem::path& target,
                      const std::function<void(const std::filesystem::path&)>& write) {
  AtomicOutputs outputs;
  outputs.stage_by_path(target, write);
  outputs.publish();
}

InjectedWriteFailure::InjectedWriteFailure(std::uintmax_t after_bytes, int error_number) {
  Injection& inj = injection();
  const std::lock_guard lock(inj.mutex);
  inj.active = true;
  inj.bytes_left = after_bytes;
  inj.error_number = error_number;
}

InjectedWriteFailure::~InjectedWriteFailure() {
  Injection& inj = injection();
  const std::lock_guard lock(inj.mutex);
  inj.active = false;
}

}  // namespace lhr
