#include "io/obj_reader.hpp"

#include <tiny_obj_loader.h>

#include <algorithm>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <string_view>
#include <system_error>
#include <utility>

#include "io/default_material.hpp"
#include "io/input_error.hpp"
#include "io/mtl_reader.hpp"
#include "io/text_scan.hpp"

namespace lhr {

namespace {

namespace fs = std::filesystem;

using text::checked_face;
using text::finite_xyz;
using text::Line;
using text::one_line;
using text::parse_int;
using text::read_file;
using text::require_text;
using text::show;
using text::without_bom;

struct ObjFace {
  int line = 0;
  std::vector<long long> indices;  // 0-based, relative indices resolved
  std::vector<int> vertices;       // the face as checked_face keeps it
  int group = 0;                   // index into ObjScan::groups
  int usemtl = -1;                 // index into ObjScan::usemtls, -1 before any
};

struct MtllibLine {
  int line = 0;
  std::vector<std::string> words;  // the names, split at blanks
  std::string whole;               // the rest of the line: one name with spaces
};

// A material switch. A line "usemtl NAME" must name a material of a
// library listed above it; a word merely starting with "usemtl"
// ("usemtlNAME") switches to NAME when one is defined and to the default
// material otherwise, as tinyobjloader has always read it.
struct UseMtl {
  int line = 0;
  std::string name;
  bool checked = true;
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
  std::vector<ObjFace> faces;
  std::vector<AttributeRef> attribute_refs;
  std::vector<MtllibLine> mtllibs;
  std::vector<UseMtl> usemtls;
  std::vector<std::string> groups;  // in order of their first face
};

// True when the keyword is followed by a blank on its line, the form in
// which g and o name a group ("g" alone at the end of a line does not).
bool blank_after(std::string_view key, std::string_view text) {
  const std::size_t after = static_cast<std::size_t>(key.data() - text.data()) + key.size();
  return after < text.size() && (text[after] == ' ' || text[after] == '\t');
}

// The text from tokens[first] to the end of the line ("" when there is none).
std::string rest_of_line(const Line& line, std::size_t first) {
  if (line.tokens.size() <= first) return {};
  const std::string_view last = line.tokens.back();
  return std::string(line.tokens[first].data(), last.data() + last.size());
}

// A group's name as it appears in the soup: "g a b" is "a b", an o line
// its whole rest; blanks trimmed, and the OBJ specification's "default"
// for faces before any group or under an empty name.
std::string group_name(std::string name) {
  name = one_line(std::move(name));
  name.erase(0, name.find_first_not_of(' '));
  return name.empty() ? "default" : name;
}

// One face line: each reference v, v/vt, v/vt/vn or v//vn checked and
// resolved (negative indices count back from the last vertex read so far).
ObjFace scan_face(const fs::path& path, const Line& line, ObjScan& scan) {
  ObjFace face;
  face.line = line.number;
  for (std::size_t t = 1; t < line.tokens.size(); ++t) {
    const std::string_view ref = line.tokens[t];
    const std::size_t slash = ref.find('/');
    const std::optional<long long> index = parse_int(ref.substr(0, slash));
    if (!index) throw InputError(path, line.number, "bad vertex reference " + show(ref) + " in face");
    if (*index == 0) throw InputError(path, line.number, "face index 0 (OBJ indices start at 1)");
    face.indices.push_back(*index > 0 ? *index - 1 : scan.n_vertices + *index);
    if (slash == std::string_view::npos) continue;
    const std::string_view rest = ref.substr(slash + 1);
    const std::size_t second = rest.find('/');
    const std::string_view parts[2] = {
        rest.substr(0, second), second == std::string_view::npos ? std::string_view() : rest.substr(second + 1)};
    // A slash promises an index after it; only v//vn leaves the vt out.
    if ((parts[0].empty() && second == std::string_view::npos) ||
        (second != std::string_view::npos && parts[1].empty())) {
      throw InputError(path, line.number, "bad vertex reference " + show(ref) + " in face");
    }
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
  return face;
}

// A line (l) or point (p) element: not part of a scene, but its indices
// must still be indices, as in a face.
void check_element_references(const fs::path& path, const Line& line) {
  for (std::size_t t = 1; t < line.tokens.size(); ++t) {
    std::string_view ref = line.tokens[t];
    while (!ref.empty()) {
      const std::size_t slash = ref.find('/');
      const std::string_view part = ref.substr(0, slash);
      const std::optional<long long> i = parse_int(part);
      if (!part.empty() && (!i || *i == 0)) {
        throw InputError(path, line.number,
                         "bad vertex reference " + show(line.tokens[t]) + " in '" + std::string(line.tokens[0]) +
                             "' line");
      }
      ref = slash == std::string_view::npos ? std::string_view() : ref.substr(slash + 1);
    }
  }
}

// The one pass over the OBJ: every line checked with its number, and
// vertices, faces, groups and material switches kept as they come.
ObjScan scan_obj(const fs::path& path, std::string_view text, const std::function<void()>& checkpoint) {
  ObjScan scan;
  std::map<std::string, int> group_index;
  std::string group = group_name("");
  int usemtl = -1;
  // Comments are kept: only '#' at the start of a line is one, and
  // material names may contain '#'.
  text::LineReader lines(text, false);
  Line line;
  for (int n = 0; lines.next(line); ++n) {
    if (checkpoint && n % text::kItemsPerCheckpoint == 0) checkpoint();
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
      ObjFace face = scan_face(path, line, scan);
      const auto [g, fresh] = group_index.emplace(group, static_cast<int>(scan.groups.size()));
      if (fresh) scan.groups.push_back(group);
      face.group = g->second;
      face.usemtl = usemtl;
      scan.faces.push_back(std::move(face));
    } else if (key == "g" && blank_after(key, text)) {
      std::string names;
      for (std::size_t t = 1; t < line.tokens.size(); ++t) names += (t > 1 ? " " : "") + std::string(line.tokens[t]);
      group = group_name(names);
    } else if (key == "o" && blank_after(key, text)) {
      group = group_name(rest_of_line(line, 1));
    } else if ((key == "l" || key == "p") && blank_after(key, text)) {
      check_element_references(path, line);
    } else if (key == "mtllib") {
      MtllibLine lib;
      lib.line = line.number;
      for (std::size_t t = 1; t < line.tokens.size(); ++t) lib.words.emplace_back(line.tokens[t]);
      if (lib.words.empty()) throw InputError(path, line.number, "mtllib without a file name");
      lib.whole = rest_of_line(line, 1);
      scan.mtllibs.push_back(std::move(lib));
    } else if (key == "usemtl") {
      if (line.tokens.size() < 2) throw InputError(path, line.number, "usemtl without a material name");
      usemtl = static_cast<int>(scan.usemtls.size());
      scan.usemtls.push_back({line.number, std::string(line.tokens[1]), true});
    } else if (key.substr(0, 6) == "usemtl") {
      usemtl = static_cast<int>(scan.usemtls.size());
      scan.usemtls.push_back({line.number, std::string(key.substr(6)), false});
    }
  }
  // Positive indices may refer to vertices listed later in the file, so the
  // range is checked against the final count.
  for (ObjFace& face : scan.faces) {
    const std::vector<long long>& written = face.indices;
    face.vertices = checked_face(face.indices, scan.n_vertices, [&](const std::string& problem) {
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

// The materials of an OBJ's libraries, read by tinyobjloader's MTL parser
// in the order of their mtllib lines, as its OBJ reader would.
struct ObjMaterials {
  std::vector<tinyobj::material_t> materials;
  std::map<std::string, int> first;         // name -> its first definition
  std::vector<std::pair<int, int>> libraries;  // (mtllib line, end of its materials)

  void read(int line, const std::string& text) {
    std::istringstream in(text);
    std::string warn, err;
    tinyobj::LoadMtl(&first, &materials, &in, &warn, &err);
    libraries.emplace_back(line, static_cast<int>(materials.size()));
  }
  // The material a usemtl switches to: the first of its name, if that
  // comes from a library listed above it; else -1.
  int lookup(const UseMtl& use) const {
    const auto it = first.find(use.name);
    if (it == first.end()) return -1;
    for (const auto& [line, end] : libraries) {
      if (it->second < end) return line < use.line ? it->second : -1;
    }
    return -1;
  }
};

}  // namespace

PolygonSoup read_obj(const fs::path& path, std::vector<std::string>& warnings,
                     const std::function<void()>& checkpoint) {
  const std::string text = without_bom(read_file(path, checkpoint));
  require_text(path, text, checkpoint);
  ObjScan scan = scan_obj(path, text, checkpoint);

  const fs::path dir = path.parent_path();
  // (line of the mtllib, materials it defines); a usemtl may only name a
  // material from a library listed above it.
  std::vector<std::pair<int, std::set<std::string>>> libraries;
  ObjMaterials read;
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
    for (const std::string& name : names) {
      const std::string library = without_bom(read_file(dir / name));
      const std::set<std::string> more = scan_mtl(dir / name, library, mtl);
      defined.insert(more.begin(), more.end());
      read.read(lib.line, library);
    }
    libraries.emplace_back(lib.line, std::move(defined));
  }
  for (const UseMtl& use : scan.usemtls) {
    if (!use.checked) continue;
    bool found = false;
    for (const auto& [library_line, materials] : libraries)
      found |= library_line < use.line && materials.count(use.name) > 0;
    if (!found) {
      throw InputError(path, use.line,
                       "usemtl names unknown material " + show(use.name) + " (not defined by an mtllib above it)");
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
  // lhr's scan and tinyobjloader's parser read a newmtl name differently
  // when it holds blanks ("newmtl my paint").
  for (const UseMtl& use : scan.usemtls) {
    if (use.checked && read.first.count(use.name) == 0) {
      throw InputError(path, use.line, "material " + show(use.name) + " was not read");
    }
  }

  PolygonSoup soup;
  soup.points = std::move(scan.points);
  soup.groups = std::move(scan.groups);
  for (const tinyobj::material_t& m : read.materials) {
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
  std::vector<int> material_of(scan.usemtls.size());
  for (std::size_t k = 0; k < scan.usemtls.size(); ++k) material_of[k] = read.lookup(scan.usemtls[k]);
  int grey = -1;
  for (ObjFace& f : scan.faces) {
    InputFace face;
    face.vertices = std::move(f.vertices);
    face.group = f.group;
    face.source_line = f.line;
    const int id = f.usemtl < 0 ? -1 : material_of[f.usemtl];
    face.material = id >= 0 ? id : default_material_index(soup.materials, grey);
    soup.faces.push_back(std::move(face));
  }
  return soup;
}

}  // namespace lhr
