#pragma once
// `lhr compare MESH.ply REF.ply`: per-vertex radiance of an exported mesh
// against `lhr reference --at-vertices` (docs/design.md §5 "How accuracy is judged").

#include <filesystem>

#include <nlohmann/json.hpp>

namespace lhr::app {

inline constexpr const char* kCompareMeshesHelp =
    "usage: lhr compare MESH.ply REF.ply [--json]\n\n"
    "With two .ply files: MESH.ply exported by lhr solve against REF.ply from lhr reference\n"
    "--at-vertices on it (same vertices): per vertex the relative luminance error\n"
    "|Y - Yref| / max(Yref, 1 % of the mean Yref); its median (p50), p95 and max, the % of\n"
    "vertices within 10 % and 15 %, the mean ratio sum Y / sum Yref and, from the reference's\n"
    "standard errors, its noise and the % of vertices off by more than 3 of them.\n";

// JSON has no infinity: an infinite value (PSNR of identical images) is null.
nlohmann::json finite_or_null(double v);

bool is_mesh_file(const std::filesystem::path& path);

// Prints the metrics (JSON with json) and returns the exit code; throws
// InputError naming the file when the vertex sets differ.
int compare_meshes(const std::filesystem::path& mesh_path, const std::filesystem::path& reference_path, bool json);

}  // namespace lhr::app
