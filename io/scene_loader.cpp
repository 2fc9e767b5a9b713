#include "io/scene_loader.hpp"

#include <tiny_obj_loader.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <string_view>

#include "io/material_overrides.hpp"
#include "io/ply_off_reader.hpp"
#include "io/scene_file.hpp"
#include "io/text_scan.hpp"
#include "io/texture_colour.hpp"
#include "mesh/surfaces.hpp"

namespace lhr {

namespace {

namespace fs = std::filesystem;

// Faces without a material, and materials whose only colour is a texture
// that cannot be found, reflect this grey (docs/design.md §3).
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
using text::without_bom;

// ------------------------------------------------------------------ OBJ / MTL

struct ObjFaceLine {
  int line = 0;
  std::vector<long long> indices;  // 0-based, relative indices resolved
};

struct MtllibLine {
  int line = 0;
  std::vector<std::string> words;  // the names as tinyobjloader splits them
  std::string whole;               // the rest of the line: one name with spaces
  std::size_t begin = 0, end = 0;  // the line's span in the text
};

// A vt/vn reference of a face, checked once the counts are known.
struct AttributeRef {
  int line = 0;
  bool normal = false;
  long long written = 0;
  long long index = 0;  // 0-based, relative indices resolved
};

struct ObjScan {
  long long n_vertices = 0;
  long long n_texcoords = 0;
  long long n_normals = 0;
  std::vector<Vec3> points;  // correctly rounded (strtod), unlike tinyobjloader's fast parser
  std::vector<ObjFaceLine> faces;
  std::vector<AttributeRef> attribute_refs;
  std::vector<MtllibLine> mtllibs;
  std::vector<std::pair<int, std::string>> usemtls;  // line, material name
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
    } else if (key == "vt") {
      ++scan.n_texcoords;
    } else if (key == "vn") {
      ++scan.n_normals;
    } else if (key == "f") {
      ObjFaceLine face{line.number, {}};
      for (std::size_t t = 1; t < line.tokens.size(); ++t) {
        const std::string_view ref = line.tokens[t];
        const std::size_t slash = ref.find('/');
        const std::string_view v = ref.substr(0, slash);
        const std::optional<long long> index = parse_int(v);
        if (!index) throw InputError(path, line.number, "bad vertex reference " + show(ref) + " in face");
        if (*index == 0) throw InputError(path, line.number, "face index 0 (OBJ indices start at 1)");
        // Negative indices count back from the last vertex read so far.
        face.indices.push_back(*index > 0 ? *index - 1 : scan.n_vertices + *index);
        // v/vt, v/vt/vn or v//vn: tinyobjloader reads whatever vt/vn index
        // it is given, so the range is checked here.
        if (slash == std::string_view::npos) continue;
        const std::string_view rest = ref.substr(slash + 1);
        const std::size_t second = rest.find('/');
        const std::string_view parts[2] = {
            rest.substr(0, second), second == std::string_view::npos ? std::string_view() : rest.substr(second + 1)};
        for (int k = 0; k < 2; ++k) {
          if (parts[k].empty()) continue;
          const std::optional<long long> i = parse_int(parts[k]);
          if (!i || *i == 0) throw InputError(path, line.number, "bad vertex reference " + show(ref) + " in face");
          const long long so_far = k == 0 ? scan.n_texcoords : scan.n_normals;
          scan.attribute_refs.push_back({line.number, k == 1, *i, *i > 0 ? *i - 1 : so_far + *i});
        }
      }
      if (face.indices.size() < 3) {
        throw InputError(path, line.number,
                         "face has " + std::to_string(face.indices.size()) +
                             " vertices (needs at least 3; truncated file?)");
      }
      scan.faces.push_back(std::move(face));
    } else if (key == "mtllib") {
      MtllibLine lib;
      lib.line = line.number;
      for (std::size_t t = 1; t < line.tokens.size(); ++t) lib.words.emplace_back(line.tokens[t]);
      if (lib.words.empty()) throw InputError(path, line.number, "mtllib without a file name");
      const std::string_view last = line.tokens.back();
      lib.whole.assign(line.tokens[1].data(), last.data() + last.size());
      lib.begin = static_cast<std::size_t>(line.tokens[0].data() - text.data());
      lib.end = static_cast<std::size_t>(last.data() + last.size() - text.data());
      scan.mtllibs.push_back(std::move(lib));
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
  for (const AttributeRef& ref : scan.attribute_refs) {
    const long long count = ref.normal ? scan.n_normals : scan.n_texcoords;
    if (ref.index < 0 || ref.index >= count) {
      throw InputError(path, ref.line,
                       std::string(ref.normal ? "normal" : "texture coordinate") + " index " +
                           std::to_string(ref.written) + " out of range (" + std::to_string(count) +
                           (ref.normal ? " vn" : " vt") + " lines)");
    }
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

// What the MTL says about one material beyond what tinyobjloader keeps:
// whether Kd was given, and the file of a map_Kd texture.
struct MtlMaterial {
  bool has_kd = false;
  std::optional<fs::path> texture;
  fs::path library;
  int line = 0;  // of its newmtl
};

// Everything read from the material libraries of one OBJ.
struct MtlScan {
  std::map<std::string, MtlMaterial> materials;  // the first definition of a name wins, as in tinyobjloader
  std::vector<std::string> ignored_keys;         // in order of first appearance
  std::vector<std::string> ignoring_files;
};

// The keys lhr reads; everything else in an MTL describes non-diffuse
// shading (Ks, Ns, Ni, d, illum, ...) that a radiosity solution cannot show.
bool is_read_key(std::string_view key) { return key == "newmtl" || key == "Kd" || key == "Ke" || key == "map_Kd"; }

// Validates Kd/Ke with line numbers (tinyobjloader silently reads bad
// numbers as 0), records map_Kd and the keys lhr ignores, and returns the
// material names the library defines. text is the library without its BOM.
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

// Hands tinyobjloader the libraries lhr resolved and read: the OBJ it parses
// names each mtllib line by its ordinal, so names with spaces and several
// libraries on one line load, and a BOM is already gone.
class ResolvedMaterials : public tinyobj::MaterialReader {
 public:
  explicit ResolvedMaterials(std::vector<std::vector<std::string>> texts) : texts_(std::move(texts)) {}
  bool operator()(const std::string& id, std::vector<tinyobj::material_t>* materials,
                  std::map<std::string, int>* names, std::string* warn, std::string* err) override {
    const std::optional<long long> k = parse_int(id);
    if (!k || *k < 0 || *k >= static_cast<long long>(texts_.size())) return false;
    for (const std::string& text : texts_[*k]) {
      std::istringstream in(text);
      tinyobj::LoadMtl(names, materials, &in, warn, err);
    }
    return true;
  }

 private:
  std::vector<std::vector<std::string>> texts_;
};

// A material's reflectance when the MTL gives a map_Kd texture and no Kd:
// the texture's mean, or the default grey with a warning when it is missing.
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

PolygonSoup load_obj(const fs::path& path, std::vector<std::string>& warnings) {
  std::string text = without_bom(read_file(path));
  require_text(path, text);
  const ObjScan scan = scan_obj(path, text);

  const fs::path dir = path.parent_path();
  // (line of the mtllib, materials it defines); a usemtl may only name a
  // material from a library listed above it, as tinyobjloader reads in order.
  std::vector<std::pair<int, std::set<std::string>>> libraries;
  std::vector<std::vector<std::string>> library_texts;
  MtlScan mtl;
  for (const MtllibLine& lib : scan.mtllibs) {
    // "mtllib my room.mtl" names one file if it exists, else each word is one.
    std::error_code ec;
    std::vector<std::string> names{lib.whole};
    if (!fs::is_regular_file(dir / lib.whole, ec)) names = lib.words;
    for (const std::string& name : names) {
      if (!fs::is_regular_file(dir / name, ec)) {
        const std::string missing = names.size() > 1 && lib.words.size() > 1 ? lib.whole : name;
        throw InputError(path, lib.line,
                         "material library " + show(missing) + " not found (looked for " + (dir / missing).string() +
                             ")");
      }
    }
    std::set<std::string> defined;
    std::vector<std::string> texts;
    for (const std::string& name : names) {
      texts.push_back(without_bom(read_file(dir / name)));
      const std::set<std::string> more = scan_mtl(dir / name, texts.back(), mtl);
      defined.insert(more.begin(), more.end());
    }
    libraries.emplace_back(lib.line, std::move(defined));
    library_texts.push_back(std::move(texts));
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
  if (!mtl.ignored_keys.empty()) {
    std::string keys, files;
    for (const std::string& k : mtl.ignored_keys) keys += (keys.empty() ? "" : ", ") + k;
    for (const std::string& f : mtl.ignoring_files) files += (files.empty() ? "" : ", ") + f;
    warnings.push_back("ignored MTL keys " + keys + " (in " + files +
                       "): lhr's surfaces are Lambertian and read only Kd, Ke and map_Kd");
  }

  // Each mtllib line becomes "mtllib K" for ResolvedMaterials; the line
  // count, and so every other line, stays as it was.
  std::string for_tinyobj = text;
  for (std::size_t k = scan.mtllibs.size(); k-- > 0;) {
    const MtllibLine& lib = scan.mtllibs[k];
    for_tinyobj.replace(lib.begin, lib.end - lib.begin, "mtllib " + std::to_string(k));
  }
  tinyobj::attrib_t attrib;
  std::vector<tinyobj::shape_t> shapes;
  std::vector<tinyobj::material_t> materials;
  std::string warn, err;
  ResolvedMaterials resolved(std::move(library_texts));
  std::istringstream obj_stream(for_tinyobj);
  if (!tinyobj::LoadObj(&attrib, &shapes, &materials, &warn, &err, &obj_stream, &resolved,
                        /*triangulate=*/false, /*default_vcols_fallback=*/false)) {
    throw InputError(path, "cannot parse OBJ: " + one_line(err));
  }
  std::set<std::string> loaded;
  for (const tinyobj::material_t& m : materials) loaded.insert(m.name);
  for (const auto& [line, name] : scan.usemtls) {
    if (!loaded.count(name)) throw InputError(path, line, "material " + show(name) + " was not read");
  }

  if (attrib.vertices.size() != 3 * scan.points.size()) {
    throw InputError(path, "cannot parse OBJ: vertex count differs between readers");
  }
  PolygonSoup soup;
  soup.points = scan.points;
  for (const tinyobj::material_t& m : materials) {
    Material material;
    material.name = m.name;
    material.reflectance = Rgb(m.diffuse[0], m.diffuse[1], m.diffuse[2]);
    const auto it = mtl.materials.find(m.name);
    if (it != mtl.materials.end() && !it->second.has_kd && it->second.texture) {
      material.reflectance = texture_reflectance(m.name, it->second, warnings);
    }
    material.emission = Rgb(m.emission[0], m.emission[1], m.emission[2]);
    soup.materials.push_back(material);
  }
  int default_material = -1;
  std::map<std::string, int> group_index;

  std::size_t scanned = 0;
  for (const tinyobj::shape_t& shape : shapes) {
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
    // 8-bit white is reflectance 1, as Kd 1 in an MTL (docs/design.md §3).
    for (int k = 0; k < 3; ++k) m.reflectance[k] = key[k] / 255.0;
    soup.materials.push_back(m);
  }
  return it->second;
}

PolygonSoup load_ply_off(const fs::path& path) {
  const StoredMesh stored = read_ply_off(path, FaceIndices::kInRange);

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

// The geometry of one file, as read; its reflectance-1 warning is left to
// the caller, which may still override the materials.
PolygonSoup read_geometry(const fs::path& path, std::vector<std::string>& warnings) {
  const std::string ext = extension_of(path);
  if (ext == ".obj") return load_obj(path, warnings);
  if (ext == ".ply" || ext == ".off") return load_ply_off(path);
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
    append_soup(soup, read_geometry(file.meshes[k], result.warnings), static_cast<int>(k), origin);
  }
  apply_material_overrides(soup, origin, file.overrides, path);
  warn_of_reflectance_one(geometry, soup, result.warnings);
  scene.settings = file.settings;
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
  scene.camera = file.camera ? *file.camera : framing_camera(scene);
  return result;
}

}  // namespace lhr
