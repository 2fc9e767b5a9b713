#include "io/scene_loader.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <map>
#include <optional>
#include <sstream>
#include <string>
#include <functional>

#include "io/default_material.hpp"
#include "io/material_overrides.hpp"
#include "io/obj_reader.hpp"
#include "io/ply_off_reader.hpp"
#include "io/scene_file.hpp"
#include "io/text_scan.hpp"
#include "mesh/surfaces.hpp"

namespace lhr {

namespace {

namespace fs = std::filesystem;

using text::checked_face;
using text::extension_of;
using text::show;

// Colours are rounded to 8 bits so that faces of one colour share a material.
int colour_material(const Rgb& colour, std::map<std::array<int, 3>, int>& by_key, PolygonSoup& soup) {
  std::array<int, 3> key;
  for (int k = 0; k < 3; ++k) key[k] = static_cast<int>(std::lround(255.0 * std::clamp(colour[k], 0.0, 1.0)));
  auto [it, inserted] = by_key.emplace(key, static_cast<int>(soup.materials.size()));
  if (inserted) {
    Material m;
    char name[16];
    std::snprintf(name, sizeof name, "rgb_%02x%02x%02x", key[0], key[1], key[2]);
    m.name = name;
    // 8-bit white is reflectance 1, as Kd 1 in an MTL (docs/design.md §3).
    for (int k = 0; k < 3; ++k) m.reflectance[k] = key[k] / 255.0;
    soup.materials.push_back(m);
  }
  return it->second;
}

PolygonSoup load_ply_off(const fs::path& path, const std::function<void()>& checkpoint) {
  const StoredMesh stored = read_ply_off(path, FaceIndices::kInRange, checkpoint);

  // The text checks above give line numbers; these repeat them for binary
  // files, where only the element index can be named.
  PolygonSoup soup;
  for (std::size_t i = 0; i < stored.points.size(); ++i) {
    const Vec3& p = stored.points[i];
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2])) {
      throw InputError(path, "vertex " + std::to_string(i) + ": non-finite coordinate");
    }
    soup.points.push_back(p);
  }
  if (stored.faces.empty()) throw InputError(path, "no faces (empty scene)");
  soup.groups.push_back(path.stem().string());
  std::map<std::array<int, 3>, int> by_key;
  int grey = -1;
  for (std::size_t f = 0; f < stored.faces.size(); ++f) {
    InputFace face;
    face.vertices = checked_face(
        std::vector<long long>(stored.faces[f].begin(), stored.faces[f].end()),
        static_cast<long long>(soup.points.size()),
        [&](const std::string& p) { return InputError(path, "face " + std::to_string(f) + ": " + p); });
    face.source_line = static_cast<int>(f);
    std::optional<Rgb> colour = stored.face_colours[f];
    if (!colour) {
      Rgb sum(0, 0, 0);
      bool all = true;
      for (int v : face.vertices) {
        if (stored.vertex_colours[v])
          sum += *stored.vertex_colours[v];
        else
          all = false;
      }
      if (all) colour = sum / static_cast<double>(face.vertices.size());
    }
    face.material = colour ? colour_material(*colour, by_key, soup) : default_material_index(soup.materials, grey);
    soup.faces.push_back(std::move(face));
  }
  return soup;
}

// The geometry of one file, as read; its reflectance-1 warning is left to
// the caller, which may still override the materials.
PolygonSoup read_geometry(const fs::path& path, std::vector<std::string>& warnings,
                          const std::function<void()>& checkpoint = {}) {
  const std::string ext = extension_of(path);
  if (ext == ".obj") return read_obj(path, warnings, checkpoint);
  if (ext == ".ply" || ext == ".off") return load_ply_off(path, checkpoint);
  throw InputError(path, "unsupported file type " + show(ext) + " (expected .obj, .ply or .off)");
}

// docs/design.md §3: reflectance 1 is allowed, but light between such surfaces
// never dies out, so a closed scene of them does not converge.
void warn_of_reflectance_one(const fs::path& path, const PolygonSoup& soup, std::vector<std::string>& warnings) {
  std::string white;
  for (const Material& m : soup.materials) {
    if (std::max({m.reflectance[0], m.reflectance[1], m.reflectance[2]}) >= 1.0) {
      white += (white.empty() ? "" : ", ") + show(m.name);
    }
  }
  if (!white.empty()) {
    warnings.push_back(path.string() + ": reflectance 1 (Kd = 1, 8-bit 255 or an override) in material(s) " +
                       white +
                       ": they absorb nothing, so light bouncing between them never dies out and the solvers "
                       "may stop at their iteration limit");
  }
}

// Adds one file's soup to a scene of several: its points and materials are
// its own, and a group of a name already seen joins that group, as groups
// of one name do within an OBJ.
void append_soup(PolygonSoup& all, PolygonSoup part, int file, SoupOrigin& origin) {
  const int point_offset = static_cast<int>(all.points.size());
  const int material_offset = static_cast<int>(all.materials.size());
  std::vector<int> group_index;
  for (const std::string& g : part.groups) {
    const auto it = std::find(all.groups.begin(), all.groups.end(), g);
    group_index.push_back(static_cast<int>(it - all.groups.begin()));
    if (it == all.groups.end()) all.groups.push_back(g);
  }
  all.points.insert(all.points.end(), part.points.begin(), part.points.end());
  for (Material& m : part.materials) {
    origin.material_names.push_back(m.name);
    all.materials.push_back(std::move(m));
  }
  for (InputFace& face : part.faces) {
    for (int& v : face.vertices) v += point_offset;
    face.material += material_offset;
    face.group = group_index.at(face.group);
    all.faces.push_back(std::move(face));
    origin.face_file.push_back(file);
  }
}

}  // namespace

PolygonSoup load_polygon_soup(const std::filesystem::path& path, std::vector<std::string>* warnings) {
  std::vector<std::string> ignored;
  std::vector<std::string>& notes = warnings ? *warnings : ignored;
  PolygonSoup soup = read_geometry(path, notes);
  warn_of_reflectance_one(path, soup, notes);
  return soup;
}

LoadResult load_scene(const std::filesystem::path& path, const LoadOptions& options) {
  if (options.crease_angle_deg && !(std::isfinite(*options.crease_angle_deg) &&
                                    *options.crease_angle_deg >= 0.0 && *options.crease_angle_deg <= 180.0)) {
    throw std::invalid_argument("crease angle must be in [0, 180] degrees, got " +
                                std::to_string(*options.crease_angle_deg));
  }
  LoadResult result;
  Scene& scene = result.scene;
  scene.source = path.string();
  SceneFile file;
  if (extension_of(path) == ".json") {
    file = parse_scene_file(path);
  } else {
    file.meshes = {path};
    file.mesh_entries = {path.filename().string()};
  }
  // Messages about the geometry name its file, or the scene file when the
  // geometry is several files or its materials were overridden.
  const fs::path geometry = file.meshes.size() == 1 && file.overrides.empty() ? file.meshes[0] : path;
  PolygonSoup soup;
  SoupOrigin origin;
  origin.file_names = file.mesh_entries;
  for (std::size_t k = 0; k < file.meshes.size(); ++k) {
    append_soup(soup, read_geometry(file.meshes[k], result.warnings, options.checkpoint), static_cast<int>(k), origin);
  }
  apply_material_overrides(soup, origin, file.overrides, path);
  warn_of_reflectance_one(geometry, soup, result.warnings);
  scene.settings = file.settings;
  const double crease =
      options.crease_angle_deg.value_or(scene.settings.crease_angle_deg.value_or(kDefaultCreaseAngleDeg));
  SurfaceSplit split = split_into_surfaces(soup, crease, options.checkpoint);
  if (split.surfaces.empty()) throw InputError(geometry, "every face has zero area (empty scene)");
  scene.materials = std::move(soup.materials);
  scene.surfaces = std::move(split.surfaces);
  scene.dropped_zero_area_faces = split.dropped_zero_area_faces;
  if (split.dropped_zero_area_faces > 0) {
    result.warnings.push_back("dropped " + std::to_string(split.dropped_zero_area_faces) +
                              " zero-area faces");
  }
  if (split.non_manifold_edges > 0) {
    result.warnings.push_back(geometry.string() + ": " + std::to_string(split.non_manifold_edges) +
                              " edges are shared by more than two faces; surfaces are cut along them");
  }
  for (const auto& [emitter, under] : split.lifted_emitters) {
    std::ostringstream note;
    note << geometry.string() << ": emitter " << scene.surfaces[emitter].name << " lies on the plane of "
         << scene.surfaces[under].name << "; it is placed " << split.lift_distance << " in front of it";
    result.warnings.push_back(note.str());
  }
  scene.camera = file.camera ? *file.camera : framing_camera(scene);
  return result;
}

}  // namespace lhr
