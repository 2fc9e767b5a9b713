#pragma once
// A generated scene as files a user can open and edit: OBJ, MTL and scene
// JSON (docs/scene-format.md), written by `lhr scene`.

#include <filesystem>
#include <string>

#include "io/paper_scenes.hpp"

namespace lhr {

// Writes DIR/NAME.obj, DIR/NAME.mtl and DIR/NAME.scene.json, published
// together (io/atomic_file.hpp). Throws std::invalid_argument for a name
// that is not a plain file name, std::runtime_error for a failed write.
void write_scene_files(const PaperScene& scene, const std::filesystem::path& dir,
                       const std::string& name);

}  // namespace lhr
