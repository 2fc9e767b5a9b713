#include "io/output_dir.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>
#include <string>
#include <system_error>

namespace lhr {

namespace {

[[noreturn]] void cannot_write_here(const std::filesystem::path& dir, int error_number) {
  throw std::runtime_error(dir.string() + ": cannot write here: " + std::strerror(error_number));
}

}  // namespace

void check_output_directory(const std::filesystem::path& dir) {
  std::error_code ec;
  if (!std::filesystem::exists(dir, ec)) throw std::runtime_error(dir.string() + ": output directory does not exist");
  if (!std::filesystem::is_directory(dir, ec)) throw std::runtime_error(dir.string() + ": is not a directory");
  const std::filesystem::path probe = dir / (".lhr-probe-" + std::to_string(::getpid()));
  const int fd = ::open(probe.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0600);
  if (fd < 0) cannot_write_here(dir, errno);
  const char byte = 0;
  int error_number = 0;
  if (::write(fd, &byte, 1) != 1) error_number = errno;
  if (::close(fd) != 0 && error_number == 0) error_number = errno;
  ::unlink(probe.c_str());
  if (error_number != 0) cannot_write_here(dir, error_number);
}

void prepare_output_directory(const std::filesystem::path& dir) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) throw std::runtime_error(dir.string() + ": cannot create the output directory: " + ec.message());
  check_output_directory(dir);
}

void check_output_file_location(const std::filesystem::path& file) {
  check_output_directory(file.has_parent_path() ? file.parent_path() : std::filesystem::path("."));
}

OutputDirectoryLock::OutputDirectoryLock(const std::filesystem::path& dir) {
  fd_ = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd_ < 0) throw std::runtime_error(dir.string() + ": cannot open the output directory: " + std::strerror(errno));
  int r;
  do {
    r = ::flock(fd_, LOCK_EX | LOCK_NB);
  } while (r != 0 && errno == EINTR);
  if (r != 0) {
    const int error_number = errno;
    ::close(fd_);
    fd_ = -1;
    if (error_number == EWOULDBLOCK) {
      throw std::runtime_error(dir.string() +
                               ": another lhr solve is writing to this directory; wait for it or choose another --out");
    }
    throw std::runtime_error(dir.string() + ": cannot lock the output directory: " + std::strerror(error_number));
  }
}

OutputDirectoryLock::~OutputDirectoryLock() {
  if (fd_ >= 0) ::close(fd_);
}

}  // namespace lhr
