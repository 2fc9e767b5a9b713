#pragma once
// Helpers shared by the test executables.

#include <sys/types.h>

#include <filesystem>
#include <string>
#include <vector>

namespace lhr::test {

// Under AddressSanitizer resident sizes and run times mean nothing (shadow
// memory, quarantine, several times slower): tests of them skip those checks.
#if defined(__SANITIZE_ADDRESS__)
inline constexpr bool kUnderAddressSanitizer = true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
inline constexpr bool kUnderAddressSanitizer = true;
#else
inline constexpr bool kUnderAddressSanitizer = false;
#endif
#else
inline constexpr bool kUnderAddressSanitizer = false;
#endif

struct CommandResult {
  int exit_code = -1;  // -1 when the process did not exit normally (crash, signal)
  std::string out;
  std::string err;
};

// Runs the built `lhr` executable with args, capturing stdout and stderr.
CommandResult run_lhr(const std::vector<std::string>& args);
// Starts the built `lhr` executable with args in the background, its stderr
// to err_file; the pid, or -1 when it could not be started.
pid_t spawn_lhr(std::vector<std::string> args, const std::filesystem::path& err_file);

std::filesystem::path source_dir();
// A fresh, empty directory for one test, removed and recreated on each call;
// all of them go when the test process exits.
std::filesystem::path fresh_dir(const std::string& name);
void write_text(const std::filesystem::path& path, const std::string& text);
// A file file_name holding text, in a fresh directory dir_name (fresh_dir); its path.
std::filesystem::path fresh_file(const std::string& dir_name, const std::string& file_name, const std::string& text);
// dir/tiny.obj and dir/tiny.mtl: a unit floor (Kd 0.7 0.6 0.5) in z = 0 under
// a 0.6 x 0.6 light (Ke 3, Kd 0) at height 0.5, facing it.
void write_lit_floor_obj(const std::filesystem::path& dir);
// dir/cube.obj and dir/cube.mtl: a closed unit cube of six inward quads, each
// glowing (Ke 1) and reflecting (Kd 0.5), so the radiance is 2 everywhere and
// nothing but a budget or a signal stops the classical method's refinement.
void write_glowing_cube(const std::filesystem::path& dir);
std::string read_text(const std::filesystem::path& path);
// The names of the entries of dir, sorted.
std::vector<std::string> file_names(const std::filesystem::path& dir);
// Number of lines of text (for one-line error messages).
int count_lines(const std::string& text);
// The texts that contain fragment, in order (a loader's warnings about one thing).
std::vector<std::string> containing(const std::vector<std::string>& texts, const std::string& fragment);

}  // namespace lhr::test
