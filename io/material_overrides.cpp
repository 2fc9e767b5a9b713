#include "io/material_overrides.hpp"

#include <algorithm>
#include <map>
#include <set>
#include <utility>

#include "io/input_error.hpp"
#include "io/text_scan.hpp"

namespace lhr {

namespace {

bool file_matches(const std::string& selector, const std::string& entry) {
  return selector == entry || selector == std::filesystem::path(entry).filename().string();
}

// The names a selector could have meant, for the error message.
std::string listing(const std::set<std::string>& names) {
  constexpr std::size_t kShown = 8;
  std::string out;
  std::size_t n = 0;
  for (const std::string& name : names) {
    if (n++ == kShown) {
      out += ", ...";
      break;
    }
    out += (out.empty() ? "" : ", ") + text::show(name);
  }
  return out;
}

}  // namespace

void apply_material_overrides(PolygonSoup& soup, const SoupOrigin& origin,
                              const std::vector<MaterialOverride>& overrides,
                              const std::filesystem::path& scene_file) {
  if (overrides.empty()) return;
  // Per face, the entries that select it, in order.
  std::vector<std::vector<int>> chosen(soup.faces.size());
  std::vector<int> selected(overrides.size(), 0);
  for (std::size_t f = 0; f < soup.faces.size(); ++f) {
    const InputFace& face = soup.faces[f];
    for (std::size_t r = 0; r < overrides.size(); ++r) {
      const MaterialOverride& o = overrides[r];
      if (o.file && !file_matches(*o.file, origin.file_names.at(origin.face_file.at(f)))) continue;
      if (o.group && *o.group != soup.groups.at(face.group)) continue;
      if (o.material && *o.material != origin.material_names.at(face.material)) continue;
      chosen[f].push_back(static_cast<int>(r));
      ++selected[r];
    }
  }
  for (std::size_t r = 0; r < overrides.size(); ++r) {
    if (selected[r] > 0) continue;
    const MaterialOverride& o = overrides[r];
    std::set<std::string> groups(soup.groups.begin(), soup.groups.end());
    std::set<std::string> materials(origin.material_names.begin(), origin.material_names.end());
    std::string why;
    if (o.group && !groups.count(*o.group)) {
      why = "there is no group " + text::show(*o.group) + " (groups: " + listing(groups) + ")";
    } else if (o.material && !materials.count(*o.material)) {
      why = "there is no material " + text::show(*o.material) + " (materials: " + listing(materials) + ")";
    } else {
      why = "no face has everything it asks for";
    }
    throw InputError(scene_file, "\"" + o.where + "\" selects no face: " + why);
  }

  // One material per (material, entries) pair that occurs.
  std::map<std::pair<int, std::vector<int>>, int> variant;
  std::vector<std::set<std::vector<int>>> uses(soup.materials.size());
  for (std::size_t f = 0; f < soup.faces.size(); ++f) uses[soup.faces[f].material].insert(chosen[f]);
  std::vector<Material> materials;
  for (std::size_t f = 0; f < soup.faces.size(); ++f) {
    InputFace& face = soup.faces[f];
    const auto key = std::make_pair(face.material, chosen[f]);
    auto [it, fresh] = variant.emplace(key, static_cast<int>(materials.size()));
    if (fresh) {
      Material m = soup.materials[face.material];
      std::string by;
      for (int r : chosen[f]) {
        const MaterialOverride& o = overrides[r];
        if (o.reflectance) m.reflectance = *o.reflectance;
        if (o.emission) m.emission = *o.emission;
        by += (by.empty() ? "" : ", ") + o.where;
      }
      if (!chosen[f].empty() && uses[face.material].size() > 1) m.name += " (" + by + ")";
      materials.push_back(std::move(m));
    }
    face.material = it->second;
  }
  soup.materials = std::move(materials);
}

}  // namespace lhr
