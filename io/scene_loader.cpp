#include "io/scene_loader.hpp"

#include <tiny_obj_loader.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <string_view>

#include "io/openmesh_import.hpp"
#include "io/ply_off_reader.hpp"
#include "io/text_scan.hpp"
#include "mesh/surfaces.hpp"

namespace lhr {

namespace {

namespace fs = std::filesystem;

// Reflectance must stay below 1 (DESIGN §3); 8-bit white in a coloured
// PLY/OFF maps to this instead of to 1.
constexpr double kMaxColourReflectance = 0.99;
constexpr double kDefaultGrey = 0.5;

using text::checked_face;
using text::extension_of;
using text::finite_xyz;
using text::Line;
using text::one_line;
using text::parse_double;
using text::parse_int;
using text::read_file;
using text::require_text;
using text::show;
using text::tokenize;

// ------------------------------------------------------------------ OBJ / MTL

struct ObjFaceLine {
  int line = 0;
  std::vector<long long> indices;  // 0-based, relative indices resolved
};

struct ObjScan {
  long long n_vertices = 0;
  std::vector<Vec3> points;  // correctly rounded (strtod), unlike tinyobjloader's fast parser
  std::vector<ObjFaceLine> faces;
  std::vector<std::pair<int, std::vector<std::string>>> mtllibs;  // line, file names
  std::vector<std::pair<int, std::string>> usemtls;               // line, material name
};

ObjScan scan_obj(const fs::path& path, std::string_view text) {
  ObjScan scan;
  // Comments are kept: tinyobjloader only treats '#' at the start of a line
  // as a comment, and material names may contain '#'.
  for (const Line& line : tokenize(text, false)) {
    const std::string_view key = line.tokens[0];
    if (key[0] == '#') continue;
    if (key == "v") {
      scan.points.push_back(finite_xyz(path, line, 1, "vertex"));
      ++scan.n_vertices;
    } else if (key == "f") {
      ObjFaceLine face{line.number, {}};
      for (std::size_t t = 1; t < line.tokens.size(); ++t) {
        const std::string_view ref = line.tokens[t];
        const std::string_view v = ref.substr(0, ref.find('/'));
        const std::optional<long long> index = parse_int(v);
        if (!index) throw InputError(path, line.number, "bad vertex reference " + show(ref) + " in face");
        if (*index == 0) throw InputError(path, line.number, "face index 0 (OBJ indices start at 1)");
        // Negative indices count back from the last vertex read so far.
        face.indices.push_back(*index > 0 ? *index - 1 : scan.n_vertices + *index);
      }
      if (face.indices.size() < 3) {
        throw InputError(path, line.number,
                         "face has " + std::to_string(face.indices.size()) +
                             " vertices (needs at least 3; truncated file?)");
      }
      scan.faces.push_back(std::move(face));
    } else if (key == "mtllib") {
      std::vector<std::string> names;
      for (std::size_t t = 1; t < line.tokens.size(); ++t) names.emplace_back(line.tokens[t]);
      if (names.empty()) throw InputError(path, line.number, "mtllib without a file name");
      scan.mtllibs.emplace_back(line.number, std::move(names));
    } else if (key == "usemtl") {
      if (line.tokens.size() < 2) throw InputError(path, line.number, "usemtl without a material name");
      scan.usemtls.emplace_back(line.number, std::string(line.tokens[1]));
    }
  }
  // Positive indices may refer to vertices listed later in the file, so the
  // range is checked against the final count.
  for (ObjFaceLine& face : scan.faces) {
    std::vector<long long> written = face.indices;
    checked_face(face.indices, scan.n_vertices, [&](const std::string& problem) {
      std::string msg = problem;
      const auto bad = std::find_if(written.begin(), written.end(),
                                    [&](long long i) { return i < 0 || i >= scan.n_vertices; });
      // Report the index as written in the file (1-based).
      if (bad != written.end()) {
        msg = "face index " + std::to_string(*bad + 1) + " out of range (" + std::to_string(scan.n_vertices) +
              " vertices)";
      }
      return InputError(path, face.line, msg);
    });
  }
  return scan;
}

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
    if (reflectance && !(*v >= 0.0 && *v < 1.0)) {
      throw InputError(mtl, line.number,
                       "Kd " + std::string(line.tokens[k]) + " of material " + show(material) +
                           " is outside [0, 1): reflectance must be non-negative and below 1 per channel");
    }
    if (!reflectance && !(std::isfinite(*v) && *v >= 0.0)) {
      throw InputError(mtl, line.number,
                       "Ke " + std::string(line.tokens[k]) + " of material " + show(material) +
                           " must be a finite, non-negative emitted radiance");
    }
  }
}

// Validates Kd/Ke with line numbers (tinyobjloader silently reads bad
// numbers as 0) and returns the material names the library defines.
std::set<std::string> scan_mtl(const fs::path& mtl) {
  const std::string text = read_file(mtl);
  require_text(mtl, text);
  std::set<std::string> names;
  std::string current;
  for (const Line& line : tokenize(text, false)) {
    const std::string_view key = line.tokens[0];
    if (key == "newmtl") {
      if (line.tokens.size() < 2) throw InputError(mtl, line.number, "newmtl without a material name");
      current = std::string(line.tokens[1]);
      names.insert(current);
    } else if (key == "Kd" || key == "Ke") {
      if (current.empty()) throw InputError(mtl, line.number, std::string(key) + " before any newmtl");
      check_rgb(mtl, line, current, key == "Kd");
    }
  }
  return names;
}

PolygonSoup load_obj(const fs::path& path) {
  const std::string text = read_file(path);
  require_text(path, text);
  const ObjScan scan = scan_obj(path, text);

  const fs::path dir = path.parent_path();
  // (line of the mtllib, materials it defines); a usemtl may only name a
  // material from a library listed above it, as tinyobjloader reads in order.
  std::vector<std::pair<int, std::set<std::string>>> libraries;
  for (const auto& [line, names] : scan.mtllibs) {
    for (const std::string& name : names) {
      const fs::path mtl = dir / name;
      std::error_code ec;
      if (!fs::is_regular_file(mtl, ec)) {
        throw InputError(path, line,
                         "material library " + show(name) + " not found (looked for " + mtl.string() + ")");
      }
      libraries.emplace_back(line, scan_mtl(mtl));
    }
  }
  for (const auto& [line, name] : scan.usemtls) {
    bool found = false;
    for (const auto& [library_line, materials] : libraries)
      found |= library_line < line && materials.count(name) > 0;
    if (!found) {
      throw InputError(
          path, line, "usemtl names unknown material " + show(name) + " (not defined by an mtllib above it)");
    }
  }
  if (scan.faces.empty()) throw InputError(path, "no faces (empty scene)");

  tinyobj::ObjReaderConfig config;
  config.triangulate = false;
  config.vertex_color = false;
  config.mtl_search_path = dir.empty() ? std::string(".") : dir.string();
  tinyobj::ObjReader reader;
  if (!reader.ParseFromFile(path.string(), config)) {
    throw InputError(path, "cannot parse OBJ: " + one_line(reader.Error()));
  }
  const tinyobj::attrib_t& attrib = reader.GetAttrib();
  std::set<std::string> loaded;
  for (const tinyobj::material_t& m : reader.GetMaterials()) loaded.insert(m.name);
  for (const auto& [line, name] : scan.usemtls) {
    if (!loaded.count(name)) {
      // tinyobjloader stops after the first readable file of an mtllib line.
      throw InputError(
          path, line,
          "material " + show(name) + " was not read; list each material library on its own mtllib line");
    }
  }

  if (attrib.vertices.size() != 3 * scan.points.size()) {
    throw InputError(path, "cannot parse OBJ: vertex count differs between readers");
  }
  PolygonSoup soup;
  soup.points = scan.points;
  for (const tinyobj::material_t& m : reader.GetMaterials()) {
    Material material;
    material.name = m.name;
    material.reflectance = Rgb(m.diffuse[0], m.diffuse[1], m.diffuse[2]);
    material.emission = Rgb(m.emission[0], m.emission[1], m.emission[2]);
    soup.materials.push_back(material);
  }
  int default_material = -1;
  std::map<std::string, int> group_index;

  std::size_t scanned = 0;
  for (const tinyobj::shape_t& shape : reader.GetShapes()) {
    std::string group = one_line(shape.name);
    group.erase(0, group.find_first_not_of(' '));
    if (group.empty()) group = "default";  // the OBJ specification's default group
    auto [g, new_group] = group_index.emplace(group, static_cast<int>(soup.groups.size()));
    if (new_group) soup.groups.push_back(group);

    const tinyobj::mesh_t& mesh = shape.mesh;
    std::size_t offset = 0;
    for (std::size_t f = 0; f < mesh.num_face_vertices.size(); ++f) {
      const std::size_t n = mesh.num_face_vertices[f];
      // The scan and tinyobjloader read the same text; if they disagree the
      // file uses syntax one of them does not understand.
      if (scanned >= scan.faces.size()) throw InputError(path, "cannot parse OBJ: unexpected extra face");
      const ObjFaceLine& expected = scan.faces[scanned++];
      std::vector<long long> indices;
      for (std::size_t k = 0; k < n; ++k) indices.push_back(mesh.indices[offset + k].vertex_index);
      offset += n;
      if (indices != expected.indices) {
        throw InputError(path, expected.line, "cannot parse this face line");
      }
      InputFace face;
      face.vertices = checked_face(indices, static_cast<long long>(soup.points.size()),
                                   [&](const std::string& p) { return InputError(path, expected.line, p); });
      face.group = g->second;
      face.source_line = expected.line;
      const int id = f < mesh.material_ids.size() ? mesh.material_ids[f] : -1;
      if (id >= 0 && id < static_cast<int>(soup.materials.size())) {
        face.material = id;
      } else {
        if (default_material < 0) {
          default_material = static_cast<int>(soup.materials.size());
          Material grey;
          grey.name = "default";
          grey.reflectance = Rgb(kDefaultGrey, kDefaultGrey, kDefaultGrey);
          soup.materials.push_back(grey);
        }
        face.material = default_material;
      }
      soup.faces.push_back(std::move(face));
    }
  }
  if (scanned != scan.faces.size()) {
    throw InputError(path, scan.faces[scanned].line, "cannot parse this face line");
  }
  return soup;
}

// ------------------------------------------------------------------ PLY / OFF

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
    for (int k = 0; k < 3; ++k) m.reflectance[k] = std::min(key[k] / 255.0, kMaxColourReflectance);
    soup.materials.push_back(m);
  }
  return it->second;
}

PolygonSoup load_openmesh(const fs::path& path) {
  // Every face is kept as read and checked below: OpenMesh's own importer
  // would drop non-manifold faces and could not hold out-of-range indices.
  PlainImporter importer;
  read_ply_off(path, importer, FaceIndices::kInRange);

  // The text checks above give line numbers; these repeat them for binary
  // files, where only the element index can be named.
  PolygonSoup soup;
  for (std::size_t i = 0; i < importer.points.size(); ++i) {
    const Vec3& p = importer.points[i];
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2])) {
      throw InputError(path, "vertex " + std::to_string(i) + ": non-finite coordinate");
    }
    soup.points.push_back(p);
  }
  if (importer.faces.empty()) throw InputError(path, "no faces (empty scene)");
  soup.groups.push_back(path.stem().string());
  std::map<std::array<int, 3>, int> by_key;
  int grey = -1;
  for (std::size_t f = 0; f < importer.faces.size(); ++f) {
    InputFace face;
    face.vertices = checked_face(
        std::vector<long long>(importer.faces[f].begin(), importer.faces[f].end()),
        static_cast<long long>(soup.points.size()),
        [&](const std::string& p) { return InputError(path, "face " + std::to_string(f) + ": " + p); });
    face.source_line = static_cast<int>(f);
    std::optional<Rgb> colour = importer.face_colours[f];
    if (!colour) {
      Rgb sum(0, 0, 0);
      bool all = true;
      for (int v : face.vertices) {
        if (importer.vertex_colours[v])
          sum += *importer.vertex_colours[v];
        else
          all = false;
      }
      if (all) colour = sum / static_cast<double>(face.vertices.size());
    }
    if (colour) {
      face.material = colour_material(*colour, by_key, soup);
    } else {
      if (grey < 0) {
        grey = static_cast<int>(soup.materials.size());
        Material m;
        m.name = "default";
        m.reflectance = Rgb(kDefaultGrey, kDefaultGrey, kDefaultGrey);
        soup.materials.push_back(m);
      }
      face.material = grey;
    }
    soup.faces.push_back(std::move(face));
  }
  return soup;
}

// --------------------------------------------------------------- scene JSON

using Json = nlohmann::json;

class JsonReader {
 public:
  explicit JsonReader(fs::path path) : path_(std::move(path)) {}

  [[noreturn]] void fail(const std::string& problem) const { throw InputError(path_, problem); }

  const Json& member(const Json& object, const std::string& key, const std::string& where) const {
    if (!object.contains(key)) fail("missing key \"" + where + key + "\"");
    return object.at(key);
  }
  double number(const Json& value, const std::string& name) const {
    if (!value.is_number()) fail("\"" + name + "\" must be a number");
    const double v = value.get<double>();
    if (!std::isfinite(v)) fail("\"" + name + "\" must be finite");
    return v;
  }
  Vec3 vec3(const Json& value, const std::string& name) const {
    if (!value.is_array() || value.size() != 3) fail("\"" + name + "\" must be an array of three numbers");
    Vec3 v;
    for (int k = 0; k < 3; ++k) v[k] = number(value[k], name + "[" + std::to_string(k) + "]");
    return v;
  }
  int positive_int(const Json& value, const std::string& name) const {
    if (!value.is_number_integer() || value.get<long long>() <= 0 || value.get<long long>() > (1 << 16)) {
      fail("\"" + name + "\" must be a positive integer (at most 65536)");
    }
    return value.get<int>();
  }

 private:
  fs::path path_;
};

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

struct SceneFile {
  fs::path mesh;
  std::optional<Camera> camera;
  SceneSettings settings;
};

SceneFile parse_scene_file(const fs::path& path) {
  const std::string text = read_file(path);
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
  const Json& mesh = r.member(root, "mesh", "");
  if (!mesh.is_string() || mesh.get<std::string>().empty()) r.fail("\"mesh\" must be a file name");
  scene.mesh = path.parent_path() / mesh.get<std::string>();
  if (root.contains("camera")) scene.camera = parse_camera(r, root.at("camera"));
  if (root.contains("meshing")) {
    const Json& m = root.at("meshing");
    if (!m.is_object()) r.fail("\"meshing\" must be an object");
    if (m.contains("max_edge")) {
      const double h = r.number(m.at("max_edge"), "meshing.max_edge");
      if (!(h > 0.0)) r.fail("\"meshing.max_edge\" must be positive");
      scene.settings.max_edge = h;
    }
    if (m.contains("crease_angle_deg")) {
      const double a = r.number(m.at("crease_angle_deg"), "meshing.crease_angle_deg");
      if (!(a >= 0.0 && a <= 180.0)) r.fail("\"meshing.crease_angle_deg\" must be in [0, 180] degrees");
      scene.settings.crease_angle_deg = a;
    }
  }
  if (root.contains("tone_map")) {
    const Json& t = root.at("tone_map");
    if (!t.is_object()) r.fail("\"tone_map\" must be an object");
    ToneMapSettings& tone = scene.settings.tone_map;
    for (const auto& [key, value] : t.items()) {
      const std::string name = "tone_map." + key;
      if (key == "kind") {
        if (!value.is_string() || (value != "tumblin-rushmeier" && value != "linear")) {
          r.fail("\"" + name + "\" must be \"tumblin-rushmeier\" or \"linear\"");
        }
        tone.kind = value.get<std::string>();
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
  const std::string mesh_ext = extension_of(scene.mesh);
  if (mesh_ext != ".obj" && mesh_ext != ".ply" && mesh_ext != ".off") {
    r.fail("\"mesh\" must name an .obj, .ply or .off file, not " + show(mesh.get<std::string>()));
  }
  std::error_code ec;
  if (!fs::is_regular_file(scene.mesh, ec)) {
    r.fail("mesh file " + show(mesh.get<std::string>()) + " not found (looked for " + scene.mesh.string() +
           ")");
  }
  return scene;
}

}  // namespace

PolygonSoup load_polygon_soup(const std::filesystem::path& path) {
  const std::string ext = extension_of(path);
  if (ext == ".obj") return load_obj(path);
  if (ext == ".ply" || ext == ".off") return load_openmesh(path);
  throw InputError(path, "unsupported file type " + show(ext) + " (expected .obj, .ply or .off)");
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
  fs::path geometry = path;
  std::optional<Camera> camera;
  if (extension_of(path) == ".json") {
    SceneFile file = parse_scene_file(path);
    geometry = file.mesh;
    camera = file.camera;
    scene.settings = file.settings;
  }
  PolygonSoup soup = load_polygon_soup(geometry);
  const double crease =
      options.crease_angle_deg.value_or(scene.settings.crease_angle_deg.value_or(kDefaultCreaseAngleDeg));
  SurfaceSplit split = split_into_surfaces(soup, crease);
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
  scene.camera = camera ? *camera : framing_camera(scene);
  return result;
}

}  // namespace lhr
