#include "io/ply_off_reader.hpp"

#include <string>

#include "io/input_error.hpp"
#include "io/off_reader.hpp"
#include "io/ply_reader.hpp"
#include "io/text_scan.hpp"

namespace lhr {

StoredMesh read_ply_off(const std::filesystem::path& path, FaceIndices faces,
                        const std::function<void()>& checkpoint) {
  const std::string ext = text::extension_of(path);
  if (ext != ".ply" && ext != ".off") {
    throw InputError(path,
                     "unknown mesh format " + text::show(path.extension().string()) + " (expected .ply or .off)");
  }
  const std::string bytes = text::read_file(path, checkpoint);
  if (bytes.empty()) throw InputError(path, "file is empty");
  return ext == ".ply" ? read_ply(path, bytes, faces, checkpoint) : read_off(path, bytes, faces, checkpoint);
}

}  // namespace lhr
