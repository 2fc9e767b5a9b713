#include "tests/fuzz/fuzz_support.hpp"

#include <unistd.h>

#include <cmath>
#include <fstream>
#include <set>
#include <string>

namespace lhr::fuzz {

namespace fs = std::filesystem;

namespace {

struct ScratchDir {
  fs::path path;
  ScratchDir() {
    std::string name = (fs::temp_directory_path() / "lhr-fuzz-XXXXXX").string();
    if (::mkdtemp(name.data()) == nullptr) finding("cannot create a scratch directory", name.c_str());
    path = name;
    ::setenv("TMPDIR", name.c_str(), 1);
  }
  ~ScratchDir() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
};

bool finite(const Vec3& p) { return std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]); }

}  // namespace

const fs::path& scratch_dir() {
  static const ScratchDir dir;
  return dir.path;
}

void write_file(const fs::path& path, std::string_view bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  if (!out) finding("cannot write the fuzz input", path.c_str());
}

void remove_file(const fs::path& path) {
  std::error_code ec;
  fs::remove(path, ec);
}

void finding(const char* what, const char* detail) {
  std::fprintf(stderr, "FUZZ FINDING: %s %s\n", what, detail);
  std::abort();
}

void check_error_message(const std::exception& e) {
  const std::string_view message = e.what();
  if (message.empty()) finding("exception with an empty message");
  if (message.find('\n') != std::string_view::npos) finding("error message spans lines:", e.what());
}

void check_no_leftovers(std::initializer_list<std::string_view> inputs) {
  const std::set<std::string_view> known(inputs);
  for (const fs::directory_entry& entry : fs::directory_iterator(scratch_dir())) {
    const std::string name = entry.path().filename().string();
    if (!known.count(name)) finding("temporary file left behind:", name.c_str());
  }
}

void check_soup(const PolygonSoup& soup) {
  for (const Vec3& p : soup.points) {
    if (!finite(p)) finding("loaded a non-finite point");
  }
  const long long n = static_cast<long long>(soup.points.size());
  for (const InputFace& face : soup.faces) {
    const std::set<int> distinct(face.vertices.begin(), face.vertices.end());
    if (distinct.size() < 3 || distinct.size() != face.vertices.size()) finding("loaded a degenerate face");
    for (int v : face.vertices) {
      if (v < 0 || v >= n) finding("loaded a face index out of range");
    }
    if (face.material < 0 || face.material >= static_cast<int>(soup.materials.size())) {
      finding("loaded a face without a valid material");
    }
    if (face.group < 0 || face.group >= static_cast<int>(soup.groups.size())) {
      finding("loaded a face without a valid group");
    }
  }
  for (const Material& m : soup.materials) {
    for (int k = 0; k < 3; ++k) {
      if (!(m.reflectance[k] >= 0.0 && m.reflectance[k] <= 1.0)) finding("loaded a reflectance outside [0, 1]");
      if (!(std::isfinite(m.emission[k]) && m.emission[k] >= 0.0)) finding("loaded a bad emission");
    }
  }
}

void check_scene(const LoadResult& result) {
  const Scene& scene = result.scene;
  if (scene.surfaces.empty()) finding("loaded a scene without surfaces");
  for (const Surface& s : scene.surfaces) {
    if (s.material < 0 || s.material >= static_cast<int>(scene.materials.size())) {
      finding("loaded a surface without a valid material");
    }
    for (const Vec3& p : s.points) {
      if (!finite(p)) finding("loaded a surface with a non-finite point");
    }
    for (const std::vector<int>& polygon : s.polygons) {
      for (int v : polygon) {
        if (v < 0 || v >= static_cast<int>(s.points.size())) finding("surface polygon index out of range");
      }
    }
    if (!finite(s.normal) || !std::isfinite(s.area)) finding("surface with a non-finite normal or area");
  }
  if (!scene.camera) finding("loaded a scene without a camera");
  const Camera& c = *scene.camera;
  if (!finite(c.eye) || !finite(c.target) || !finite(c.up) || !std::isfinite(c.fov_y_deg)) {
    finding("loaded a non-finite camera");
  }
  if (c.width <= 0 || c.height <= 0) finding("loaded a camera without pixels");
}

void check_raw(const RawMesh& mesh) {
  if (!mesh.radiance.empty() && mesh.radiance.size() != mesh.points.size()) {
    finding("raw mesh radiance does not match its points");
  }
  if (mesh.faces.empty()) finding("raw mesh without faces");
  check_conforming_mesh(mesh);
}

}  // namespace lhr::fuzz
