#pragma once
// PLY files, ASCII and binary, checked and built in one pass (io/ internal;
// read_ply_off in io/ply_off_reader.hpp picks the format).

#include <filesystem>
#include <string>

#include "io/ply_off_reader.hpp"

namespace lhr {

// bytes: the whole file, not empty. Throws InputError.
// checkpoint, when set, is called every few thousand elements.
StoredMesh read_ply(const std::filesystem::path& path, const std::string& bytes, FaceIndices faces,
                    const std::function<void()>& checkpoint = {});

}  // namespace lhr
