#pragma once
// PLY and OFF files read in one pass that checks every value as it builds
// the mesh (io/ internal). Nothing a header declares is trusted: counts,
// types and list lengths are checked against the bytes the file holds
// before anything is sized by them, so every bad file is one InputError
// naming the file and the line or element (docs/design.md §3;
// docs/robustness.md lists what the fuzzers found).

#include <filesystem>
#include <functional>
#include <limits>
#include <optional>
#include <vector>

#include "mesh/types.hpp"

namespace lhr {

// Faces hold int indices: a larger one cannot be kept as stored.
inline constexpr long long kMaxVertexIndex = std::numeric_limits<int>::max();

enum class FaceIndices {
  kInRange,   // loading a scene: >= 3 distinct vertices per face, all in range
  kAsStored,  // `lhr validate`: any int, judged afterwards by the conforming check
};

// A PLY or OFF file as stored: no vertex merging, no face repair.
struct StoredMesh {
  std::vector<Vec3> points;  // as the file stores them (a float widened exactly, a double or text kept whole)
  std::vector<std::vector<int>> faces;
  std::vector<std::optional<Rgb>> vertex_colours;  // one per point, empty optionals without colours
  std::vector<std::optional<Rgb>> face_colours;    // one per face
  // PLY vertex properties radiance_r/g/b and radiance_stderr (float or
  // double, docs/design.md §3 output); empty when the file lacks them.
  std::vector<Rgb> radiance;
  std::vector<double> radiance_stderr;
};

// Reads a .ply or .off file. Throws InputError. checkpoint, when set, is
// called between slices of the read and every few thousand elements, so
// that a caller can stop reading a large file.
StoredMesh read_ply_off(const std::filesystem::path& path, FaceIndices faces,
                        const std::function<void()>& checkpoint = {});

}  // namespace lhr
