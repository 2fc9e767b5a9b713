#include "io/mtl_reader.hpp"

#include <algorithm>
#include <cmath>
#include <string_view>
#include <system_error>

#include "io/default_material.hpp"
#include "io/input_error.hpp"
#include "io/text_scan.hpp"
#include "io/texture_colour.hpp"

namespace lhr {

namespace {

namespace fs = std::filesystem;
using text::Line;
using text::parse_double;
using text::require_text;
using text::show;
using text::tokenize;

void check_rgb(const fs::path& mtl, const Line& line, const std::string& material, bool reflectance) {
  const std::string key(line.tokens[0]);
  if (line.tokens.size() != 4) {
    throw InputError(mtl, line.number, key + " of material " + show(material) + " needs three numbers r g b");
  }
  for (int k = 1; k <= 3; ++k) {
    const std::optional<double> v = parse_double(line.tokens[k]);
    if (!v) {
      throw InputError(
          mtl, line.number,
          key + " of material " + show(material) + ": " + show(line.tokens[k]) + " is not a number");
    }
    // docs/design.md §3: Kd = 1 conserves energy and is accepted (with a warning
    // from load_polygon_soup); above 1 a surface would create light.
    if (reflectance && !(*v >= 0.0 && *v <= 1.0)) {
      throw InputError(mtl, line.number,
                       "Kd " + std::string(line.tokens[k]) + " of material " + show(material) +
                           " is outside [0, 1]: reflectance is a fraction of the light received, per channel");
    }
    if (!reflectance && !(std::isfinite(*v) && *v >= 0.0)) {
      throw InputError(mtl, line.number,
                       "Ke " + std::string(line.tokens[k]) + " of material " + show(material) +
                           " must be a finite, non-negative emitted radiance");
    }
  }
}

// The keys lhr reads; everything else in an MTL describes non-diffuse
// shading (Ks, Ns, Ni, d, illum, ...) that a radiosity solution cannot show.
bool is_read_key(std::string_view key) { return key == "newmtl" || key == "Kd" || key == "Ke" || key == "map_Kd"; }

}  // namespace

std::set<std::string> scan_mtl(const fs::path& mtl, const std::string& text, MtlScan& out) {
  require_text(mtl, text);
  std::set<std::string> names;
  std::string current;
  MtlMaterial* material = nullptr;
  bool ignores = false;
  for (const Line& line : tokenize(text, false)) {
    const std::string_view key = line.tokens[0];
    if (key[0] == '#') continue;
    if (key == "newmtl") {
      if (line.tokens.size() < 2) throw InputError(mtl, line.number, "newmtl without a material name");
      current = std::string(line.tokens[1]);
      names.insert(current);
      const auto [it, fresh] = out.materials.emplace(current, MtlMaterial{false, std::nullopt, mtl, line.number});
      material = fresh ? &it->second : nullptr;
    } else if (key == "Kd" || key == "Ke") {
      if (current.empty()) throw InputError(mtl, line.number, std::string(key) + " before any newmtl");
      check_rgb(mtl, line, current, key == "Kd");
      if (key == "Kd" && material) material->has_kd = true;
    } else if (key == "map_Kd") {
      if (current.empty()) throw InputError(mtl, line.number, "map_Kd before any newmtl");
      if (line.tokens.size() < 2) throw InputError(mtl, line.number, "map_Kd without a file name");
      // The file name is the rest of the line (it may hold spaces); the
      // options before it (-s, -o, ...) take numbers and start with '-'.
      std::size_t t = 1;
      while (t + 1 < line.tokens.size() && line.tokens[t][0] == '-') {
        ++t;
        while (t + 1 < line.tokens.size() && parse_double(line.tokens[t])) ++t;
      }
      const std::string_view last = line.tokens.back();
      if (material) {
        material->texture = mtl.parent_path() / std::string(line.tokens[t].data(), last.data() + last.size());
      }
    } else if (!is_read_key(key)) {
      ignores = true;
      const std::string name(key);
      if (std::find(out.ignored_keys.begin(), out.ignored_keys.end(), name) == out.ignored_keys.end()) {
        out.ignored_keys.push_back(name);
      }
    }
  }
  if (ignores) out.ignoring_files.push_back(mtl.filename().string());
  return names;
}

Rgb texture_reflectance(const std::string& name, const MtlMaterial& m, std::vector<std::string>& warnings) {
  std::error_code ec;
  if (!fs::is_regular_file(*m.texture, ec)) {
    warnings.push_back(m.library.string() + ":" + std::to_string(m.line) + ": material " + show(name) +
                       " has no Kd and its texture " + m.texture->string() +
                       " is missing; it reflects the default grey 0.5");
    return Rgb(kDefaultGrey, kDefaultGrey, kDefaultGrey);
  }
  return texture_mean_colour(*m.texture);
}

}  // namespace lhr
