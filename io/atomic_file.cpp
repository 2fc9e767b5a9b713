#include "io/atomic_file.hpp"

#include <random>
#include <stdexcept>
#include <system_error>
#include <unistd.h>

namespace lhr {

namespace {

std::filesystem::path temporary_beside(const std::filesystem::path& target) {
  std::random_device rd;
  const auto tag = std::to_string(::getpid()) + "-" + std::to_string(rd() % 1000000);
  // Keep the extension last: OpenMesh and OpenImageIO pick the format from it.
  std::string name = ".";
  name.append(target.stem().string()).append(".tmp-").append(tag).append(target.extension().string());
  std::filesystem::path temp = target;
  temp.replace_filename(name);
  return temp;
}

}  // namespace

void write_atomically(const std::filesystem::path& target,
                      const std::function<void(const std::filesystem::path&)>& write) {
  const std::filesystem::path dir =
      target.has_parent_path() ? target.parent_path() : std::filesystem::path(".");
  if (!std::filesystem::is_directory(dir)) {
    throw std::runtime_error(target.string() + ": output directory does not exist");
  }
  const std::filesystem::path temp = temporary_beside(target);
  try {
    write(temp);
    std::error_code ec;
    std::filesystem::rename(temp, target, ec);
    if (ec) throw std::runtime_error(target.string() + ": cannot rename temporary file: " + ec.message());
  } catch (...) {
    std::error_code ignored;
    std::filesystem::remove(temp, ignored);
    throw;
  }
}

}  // namespace lhr
