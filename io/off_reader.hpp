#pragma once
// OFF files, ASCII and binary, checked and built in one pass (io/ internal;
// read_ply_off in io/ply_off_reader.hpp picks the format).

#include <filesystem>
#include <string>

#include "io/ply_off_reader.hpp"

namespace lhr {

// bytes: the whole file, not empty. Throws InputError.
// checkpoint, when set, is called every few thousand vertices and faces.
StoredMesh read_off(const std::filesystem::path& path, const std::string& bytes, FaceIndices faces,
                    const std::function<void()>& checkpoint = {});

}  // namespace lhr
