// The fuzzers' seed and regression corpus (tests/fuzz/corpus), replayed in
// every build through the same runners as the libFuzzer harnesses: each
// input must load or fail with a one-line error (a finding aborts, see
// fuzz/fuzz_support.hpp), the inputs that once made a reader loop or
// allocate without bound are rejected, the binary layouts the readers'
// pre-checks walk are the ones the files were written with, and a seed that
// crashed the mesher after loading now fails in one line.

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "io/mesh_io.hpp"
#include "io/scene_loader.hpp"
#include "tests/fuzz/fuzz_inputs.hpp"
#include "tests/test_support.hpp"

namespace lhr {
namespace {

namespace fs = std::filesystem;

std::string read_bytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

fs::path corpus_dir(const std::string& name) { return test::source_dir() / "tests" / "fuzz" / "corpus" / name; }

std::vector<fs::path> corpus(const std::string& name) {
  std::vector<fs::path> files;
  for (const auto& entry : fs::directory_iterator(corpus_dir(name))) {
    if (entry.is_regular_file()) files.push_back(entry.path());
  }
  std::sort(files.begin(), files.end());
  return files;
}

TEST(FuzzCorpus, EveryInputLoadsOrFailsInOneLine) {
  const std::vector<std::pair<std::string, void (*)(std::string_view)>> runners = {
      {"obj", fuzz::run_obj}, {"ply", fuzz::run_ply}, {"off", fuzz::run_off}, {"scene_json", fuzz::run_scene_json}};
  for (const auto& [name, run] : runners) {
    const std::vector<fs::path> files = corpus(name);
    EXPECT_GE(files.size(), 10u) << name;
    for (const fs::path& file : files) {
      SCOPED_TRACE(file.string());
      run(read_bytes(file));
    }
  }
}

TEST(FuzzCorpus, FormerFindingsAreOneLineInputErrors) {
  // Each once made OpenMesh's reader (which read PLY/OFF files before lhr's
  // own readers) loop or allocate gigabytes, in the loader or in `lhr
  // validate` (docs/robustness.md).
  const auto dir = test::fresh_dir("fuzz_regressions");
  int seen = 0;
  for (const std::string name : {"ply", "off"}) {
    for (const fs::path& file : corpus(name)) {
      if (file.filename().string().rfind("regression_", 0) != 0) continue;
      ++seen;
      const fs::path copy = dir / file.filename();
      fs::copy_file(file, copy, fs::copy_options::overwrite_existing);
      for (const bool raw : {false, true}) {
        try {
          if (raw) {
            read_raw_mesh(copy);
          } else {
            load_polygon_soup(copy);
          }
          ADD_FAILURE() << copy << " loaded (raw " << raw << ")";
        } catch (const InputError& e) {
          const std::string what = e.what();
          EXPECT_EQ(what.rfind(copy.string() + ":", 0), 0u) << what;
          EXPECT_EQ(what.find('\n'), std::string::npos) << what;
        }
      }
    }
  }
  EXPECT_EQ(seen, 4);
}

TEST(FuzzCorpus, BinaryFilesReadAsWritten) {
  // The seeds were written by hand with these coordinates and faces; the
  // binary readers must agree with their layout.
  const std::vector<Vec3> points = {{0, 0, 0}, {0, 0, 1}, {1, 0, 1}, {1, 0, 0}};
  const std::vector<std::vector<int>> faces = {{0, 1, 2}, {0, 2, 3}};
  for (const char* name : {"ply/quad_le.ply", "ply/quad_be.ply", "off/binary.off", "off/binary_colour.off"}) {
    SCOPED_TRACE(name);
    const RawMesh raw = read_raw_mesh(corpus_dir("") / name);
    EXPECT_EQ(raw.points, points);
    EXPECT_EQ(raw.faces, faces);
    const PolygonSoup soup = load_polygon_soup(corpus_dir("") / name);
    ASSERT_EQ(soup.faces.size(), 2u);
    const std::string material = soup.materials[soup.faces[0].material].name;
    // PLY vertex colours (200, 100, 50) averaged per face; the coloured OFF
    // stores (10, 20, 30) per face after (200, 100, 50) per vertex.
    EXPECT_EQ(material, std::string(name) == "off/binary.off"          ? "default"
                        : std::string(name) == "off/binary_colour.off" ? "rgb_0a141e"
                                                                       : "rgb_c86432");
  }
}

TEST(FuzzCorpus, DuplicatedFaceIsAnErrorNotACrash) {
  // From the OBJ seed slashes.obj, which loads: a triangle listed twice
  // leaves its surface without a boundary, and meshing it followed null
  // pointers inside CGAL (a segmentation fault before the fix).
  const auto dir = test::fresh_dir("fuzz_duplicated_face");
  test::write_text(dir / "twice.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 3\n");
  const auto r = test::run_lhr({"mesh", (dir / "twice.obj").string(), "--out", (dir / "out.ply").string()});
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_EQ(test::count_lines(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("boundary"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "out.ply"));
}

}  // namespace
}  // namespace lhr
