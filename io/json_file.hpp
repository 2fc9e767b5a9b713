#pragma once
// JSON documents written atomically (stats.json and other reports).

#include <filesystem>

#include <nlohmann/json.hpp>

#include "io/atomic_file.hpp"

namespace lhr {

void write_json_file(const std::filesystem::path& path, const nlohmann::json& document);
// The same, staged in a set of outputs published together.
void write_json_file(AtomicOutputs& outputs, const std::filesystem::path& path, const nlohmann::json& document);

}  // namespace lhr
