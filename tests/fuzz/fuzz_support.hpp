#pragma once
// Shared by the libFuzzer harnesses of the loaders (issue 6, docs/robustness.md).
// The loaders take paths, so each input is written to fixed names in a
// scratch directory of this process. A loader may only return or throw a
// std::exception whose message is one non-empty line (README "Bad input");
// anything else is a finding and aborts, which libFuzzer records as a crash.

#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <string_view>

#include "io/scene_loader.hpp"
#include "mesh/validate.hpp"

namespace lhr::fuzz {

// A fresh directory for this process, also made TMPDIR so the loaders'
// own temporary files land in it; removed at exit.
const std::filesystem::path& scratch_dir();

void write_file(const std::filesystem::path& path, std::string_view bytes);
void remove_file(const std::filesystem::path& path);

[[noreturn]] void finding(const char* what, const char* detail = "");

// Aborts unless the message is one non-empty line.
void check_error_message(const std::exception& e);

// Aborts when the scratch directory holds a file the loaders left behind
// (their temporaries must be removed on every path, success or error).
void check_no_leftovers(std::initializer_list<std::string_view> inputs);

// What the loaders promise on success (scene_loader.hpp, surfaces.hpp
// preconditions): finite points, faces of >= 3 distinct in-range vertices,
// valid material and group indices.
void check_soup(const PolygonSoup& soup);
void check_scene(const LoadResult& result);
// read_raw_mesh keeps the file as stored, so only sizes are promised; the
// validator (`lhr validate`) must then cope with whatever indices it holds.
void check_raw(const RawMesh& mesh);

template <class Load>
void expect_clean(Load&& load) {
  try {
    load();
  } catch (const std::exception& e) {
    check_error_message(e);
  }
}

}  // namespace lhr::fuzz
