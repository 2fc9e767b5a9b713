#include "io/scene_file.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "io/json_reader.hpp"
#include "io/text_scan.hpp"

namespace lhr {

namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;
using text::extension_of;
using text::one_line;
using text::show;

Camera parse_camera(const JsonReader& r, const Json& c) {
  if (!c.is_object()) r.fail("\"camera\" must be an object");
  Camera camera;
  camera.eye = r.vec3(r.member(c, "eye", "camera."), "camera.eye");
  camera.target = r.vec3(r.member(c, "target", "camera."), "camera.target");
  camera.up = r.vec3(r.member(c, "up", "camera."), "camera.up");
  camera.fov_y_deg = r.number(r.member(c, "fov_y_deg", "camera."), "camera.fov_y_deg");
  camera.width = r.positive_int(r.member(c, "width", "camera."), "camera.width");
  camera.height = r.positive_int(r.member(c, "height", "camera."), "camera.height");
  if (!(camera.fov_y_deg > 0.0 && camera.fov_y_deg < 180.0))
    r.fail("\"camera.fov_y_deg\" must be in (0, 180) degrees");
  const Vec3 view = camera.target - camera.eye;
  if (view.norm() == 0.0) r.fail("camera eye and target are the same point");
  if (OpenMesh::cross(view.normalized(), camera.up).norm() <= 1e-9 * camera.up.norm() ||
      camera.up.norm() == 0.0) {
    r.fail("\"camera.up\" must be non-zero and not parallel to the viewing direction");
  }
  return camera;
}

void parse_meshing(const JsonReader& r, const Json& m, SceneSettings& settings) {
  if (!m.is_object()) r.fail("\"meshing\" must be an object");
  if (m.contains("max_edge")) {
    const double h = r.number(m.at("max_edge"), "meshing.max_edge");
    if (!(h > 0.0)) r.fail("\"meshing.max_edge\" must be positive");
    settings.max_edge = h;
  }
  if (m.contains("crease_angle_deg")) {
    const double a = r.number(m.at("crease_angle_deg"), "meshing.crease_angle_deg");
    if (!(a >= 0.0 && a <= 180.0)) r.fail("\"meshing.crease_angle_deg\" must be in [0, 180] degrees");
    settings.crease_angle_deg = a;
  }
}

void parse_tone_map(const JsonReader& r, const Json& t, ToneMapSettings& tone) {
  if (!t.is_object()) r.fail("\"tone_map\" must be an object");
  for (const auto& [key, value] : t.items()) {
    const std::string name = "tone_map." + key;
    if (key == "kind") {
      const std::optional<ToneMapKind> kind =
          value.is_string() ? tone_map_kind_named(value.get<std::string>()) : std::nullopt;
      if (!kind) r.fail("\"" + name + "\" must be \"tumblin-rushmeier\" or \"linear\"");
      tone.kind = *kind;
      continue;
    }
    const double v = r.number(value, name);
    if (key == "world_adaptation" || key == "white") {
      if (!(v >= 0.0)) r.fail("\"" + name + "\" must be 0 (automatic) or positive");
      (key == "white" ? tone.white : tone.world_adaptation) = v;
    } else if (key == "units_to_cd_m2" || key == "display_max_cd_m2" || key == "gamma") {
      if (!(v > 0.0)) r.fail("\"" + name + "\" must be positive");
      (key == "gamma" ? tone.gamma : key == "units_to_cd_m2" ? tone.units_to_cd_m2 : tone.display_max_cd_m2) = v;
    } else if (key == "max_contrast") {
      if (!(v > 1.0)) r.fail("\"" + name + "\" must be above 1");
      tone.max_contrast = v;
    } else {
      r.fail("unknown key \"" + name + "\" (kind, world_adaptation, units_to_cd_m2, display_max_cd_m2, "
             "max_contrast, gamma, white)");
    }
  }
}

// "mesh": one geometry file, or a list of them that together are the scene.
std::vector<std::string> parse_mesh_entries(const JsonReader& r, const Json& mesh) {
  std::vector<std::string> entries;
  if (mesh.is_string()) {
    entries.push_back(mesh.get<std::string>());
  } else if (mesh.is_array() && !mesh.empty()) {
    for (const Json& m : mesh) {
      if (!m.is_string()) r.fail("\"mesh\" must be a file name or a list of file names");
      entries.push_back(m.get<std::string>());
    }
  } else {
    r.fail("\"mesh\" must be a file name or a non-empty list of file names");
  }
  for (const std::string& entry : entries) {
    if (entry.empty()) r.fail("\"mesh\" must be a file name, not \"\"");
  }
  return entries;
}

// Checked after the other keys, so that a scene file's key errors come first.
void resolve_meshes(const JsonReader& r, const std::vector<std::string>& entries, SceneFile& scene) {
  for (const std::string& entry : entries) {
    const fs::path file = r.path().parent_path() / entry;
    const std::string ext = extension_of(file);
    if (ext != ".obj" && ext != ".ply" && ext != ".off") {
      r.fail("\"mesh\" must name an .obj, .ply or .off file, not " + show(entry));
    }
    if (std::count(entries.begin(), entries.end(), entry) > 1) r.fail("\"mesh\" lists " + show(entry) + " twice");
    std::error_code ec;
    if (!fs::is_regular_file(file, ec)) {
      r.fail("mesh file " + show(entry) + " not found (looked for " + file.string() + ")");
    }
    scene.meshes.push_back(file);
    scene.mesh_entries.push_back(entry);
  }
}

std::vector<MaterialOverride> parse_overrides(const JsonReader& r, const Json& list,
                                              const std::vector<std::string>& mesh_entries) {
  if (!list.is_array()) r.fail("\"materials\" must be a list of objects");
  std::vector<MaterialOverride> overrides;
  for (std::size_t i = 0; i < list.size(); ++i) {
    MaterialOverride o;
    o.where = "materials[" + std::to_string(i) + "]";
    const Json& entry = list[i];
    if (!entry.is_object()) r.fail("\"" + o.where + "\" must be an object");
    for (const auto& [key, value] : entry.items()) {
      const std::string name = o.where + "." + key;
      if (key == "file" || key == "group" || key == "material") {
        if (!value.is_string() || value.get<std::string>().empty()) r.fail("\"" + name + "\" must be a name");
        (key == "file" ? o.file : key == "group" ? o.group : o.material) = value.get<std::string>();
      } else if (key == "reflectance") {
        const Rgb kd = r.colour(value, name);
        for (int k = 0; k < 3; ++k) {
          // docs/design.md §3: above 1 a surface would create light.
          if (!(kd[k] >= 0.0 && kd[k] <= 1.0)) {
            r.fail("\"" + name + "\" must be in [0, 1] per channel: reflectance is a fraction of the light received");
          }
        }
        o.reflectance = kd;
      } else if (key == "emission") {
        const Rgb ke = r.colour(value, name);
        if (!(ke[0] >= 0.0 && ke[1] >= 0.0 && ke[2] >= 0.0)) {
          r.fail("\"" + name + "\" must be a non-negative emitted radiance per channel");
        }
        o.emission = ke;
      } else {
        r.fail("unknown key \"" + name + "\" (file, group, material, reflectance, emission)");
      }
    }
    if (!o.file && !o.group && !o.material) {
      r.fail("\"" + o.where + "\" selects nothing: give a file, a group or a material (or several)");
    }
    if (!o.reflectance && !o.emission) r.fail("\"" + o.where + "\" changes nothing: give reflectance or emission");
    if (o.file) {
      const bool known = std::any_of(mesh_entries.begin(), mesh_entries.end(), [&](const std::string& e) {
        return *o.file == e || *o.file == fs::path(e).filename().string();
      });
      if (!known) r.fail("\"" + o.where + ".file\" " + show(*o.file) + " is not one of the \"mesh\" files");
    }
    overrides.push_back(std::move(o));
  }
  return overrides;
}

}  // namespace

SceneFile parse_scene_file(const fs::path& path) {
  const std::string text = text::read_file(path);
  Json root;
  try {
    root = Json::parse(text);
  } catch (const Json::parse_error& e) {
    const std::size_t at = std::min<std::size_t>(e.byte > 0 ? e.byte - 1 : 0, text.size());
    const int line = 1 + static_cast<int>(std::count(text.begin(), text.begin() + at, '\n'));
    std::string what = e.what();
    const std::size_t colon = what.find(": ");
    if (colon != std::string::npos) what = what.substr(colon + 2);
    throw InputError(path, line, "invalid JSON: " + one_line(what));
  }
  const JsonReader r(path);
  if (!root.is_object()) r.fail("a scene file must be a JSON object");
  SceneFile scene;
  const std::vector<std::string> entries = parse_mesh_entries(r, r.member(root, "mesh", ""));
  if (root.contains("camera")) scene.camera = parse_camera(r, root.at("camera"));
  if (root.contains("meshing")) parse_meshing(r, root.at("meshing"), scene.settings);
  if (root.contains("tone_map")) parse_tone_map(r, root.at("tone_map"), scene.settings.tone_map);
  if (root.contains("materials")) scene.overrides = parse_overrides(r, root.at("materials"), entries);
  resolve_meshes(r, entries, scene);
  return scene;
}

}  // namespace lhr
