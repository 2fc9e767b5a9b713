#pragma once
// Outputs are written to a temporary name beside the target and renamed, so
// a failure never leaves a half-written file or destroys an existing one.

#include <filesystem>
#include <functional>

namespace lhr {

// Calls write(temp_path); on success renames temp_path to target, on any
// exception removes temp_path and rethrows. The temporary lives in the
// target's directory so the rename is atomic.
void write_atomically(const std::filesystem::path& target,
                      const std::function<void(const std::filesystem::path& temp_path)>& write);

}  // namespace lhr
