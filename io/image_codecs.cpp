#include "io/image_codecs.hpp"

#include <dlfcn.h>
#include <link.h>

#include <cstdlib>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

// Set by io/CMakeLists.txt: the module's file name, where it is built, where
// it is installed, and where that is from the directories the lhr binary and
// the Python module are installed in.
#ifndef LHR_IMAGE_CODECS_FILE
#error "io/CMakeLists.txt defines LHR_IMAGE_CODECS_FILE and the module's directories"
#endif

namespace lhr::image_codecs {

namespace {

struct Loaded {
  const Table* table = nullptr;
  std::string error;  // when table is null: every place looked in, and why each failed
};

// Where the module may be, first match wins: only the path LHR_IMAGE_CODECS
// names, when it is set; else beside the binary holding this code, as
// installed (bin/ or the Python module's directory), then the configured
// install prefix, then the build tree.
std::vector<std::filesystem::path> candidates() {
  std::vector<std::filesystem::path> out;
  if (const char* explicit_path = std::getenv("LHR_IMAGE_CODECS"); explicit_path && *explicit_path) {
    out.emplace_back(explicit_path);
    return out;
  }
  Dl_info info{};
  link_map* holder_map = nullptr;
  if (dladdr1(reinterpret_cast<void*>(&codecs), &info, reinterpret_cast<void**>(&holder_map), RTLD_DL_LINKMAP) != 0 &&
      holder_map) {
    // The executable's own entry has an empty name.
    std::error_code ec;
    const std::filesystem::path holder = *holder_map->l_name
                                             ? std::filesystem::path(holder_map->l_name)
                                             : std::filesystem::canonical("/proc/self/exe", ec);
    for (const char* relative : {LHR_IMAGE_CODECS_FROM_BINDIR, LHR_IMAGE_CODECS_FROM_PYTHON_DIR}) {
      if (!holder.empty()) out.push_back(holder.parent_path() / relative / LHR_IMAGE_CODECS_FILE);
    }
  }
  out.push_back(std::filesystem::path(LHR_IMAGE_CODECS_INSTALL_DIR) / LHR_IMAGE_CODECS_FILE);
  out.push_back(std::filesystem::path(LHR_IMAGE_CODECS_BUILD_DIR) / LHR_IMAGE_CODECS_FILE);
  return out;
}

Loaded load() {
  Loaded loaded;
  std::string tried;
  for (const std::filesystem::path& path : candidates()) {
    std::error_code ec;
    if (!std::filesystem::exists(path, ec)) {
      tried += (tried.empty() ? "" : ", ") + path.lexically_normal().string();
      continue;
    }
    void* handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!handle) {
      const char* why = dlerror();
      loaded.error = path.string() + ": cannot load the image module: " + (why ? why : "unknown error");
      return loaded;
    }
    using Entry = const Table* (*)();
    const auto entry = reinterpret_cast<Entry>(dlsym(handle, kEntryPoint));
    const Table* table = entry ? entry() : nullptr;
    if (!table || table->abi_version != kAbiVersion) {
      loaded.error = path.string() + ": not the image module of this lhr (another version?)";
      return loaded;
    }
    loaded.table = table;
    return loaded;
  }
  loaded.error = std::string("cannot find lhr's image module ") + LHR_IMAGE_CODECS_FILE + " (looked for " + tried +
                 ")" + (std::getenv("LHR_IMAGE_CODECS") ? "" : "; set LHR_IMAGE_CODECS to its path");
  return loaded;
}

}  // namespace

const Table& codecs() {
  static const Loaded loaded = load();  // once, thread-safe
  if (!loaded.table) throw std::runtime_error(loaded.error);
  return *loaded.table;
}

}  // namespace lhr::image_codecs
