#pragma once
// An OBJ's material libraries (MTL), checked line by line (io/ internal).
// tinyobjloader reads their Kd and Ke (io/obj_reader.cpp) but silently
// reads a bad number as 0 and keeps no texture; this scan reports the one
// with its line and records the other.

#include <filesystem>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "mesh/types.hpp"

namespace lhr {

// What the MTL says about one material beyond what tinyobjloader keeps:
// whether Kd was given, and the file of a map_Kd texture.
struct MtlMaterial {
  bool has_kd = false;
  std::optional<std::filesystem::path> texture;
  std::filesystem::path library;
  int line = 0;  // of its newmtl
};

// Everything read from the material libraries of one OBJ.
struct MtlScan {
  std::map<std::string, MtlMaterial> materials;  // the first definition of a name wins, as in tinyobjloader
  std::vector<std::string> ignored_keys;         // in order of first appearance
  std::vector<std::string> ignoring_files;
};

// Validates Kd/Ke with line numbers, records map_Kd and the keys lhr
// ignores, and returns the material names the library defines. text is the
// library without its BOM. Throws InputError.
std::set<std::string> scan_mtl(const std::filesystem::path& mtl, const std::string& text, MtlScan& out);

// A material's reflectance when the MTL gives a map_Kd texture and no Kd:
// the texture's mean, or the default grey with a warning when it is missing.
Rgb texture_reflectance(const std::string& name, const MtlMaterial& m, std::vector<std::string>& warnings);

}  // namespace lhr
