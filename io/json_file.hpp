#pragma once
// JSON documents written atomically (stats.json and other reports).

#include <filesystem>

#include <nlohmann/json.hpp>

namespace lhr {

void write_json_file(const std::filesystem::path& path, const nlohmann::json& document);

}  // namespace lhr
