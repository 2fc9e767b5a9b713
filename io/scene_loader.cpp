#include "io/scene_loader.hpp"

#include <tiny_obj_loader.h>
#include <unistd.h>
#include <OpenMesh/Core/IO/IOManager.hh>
#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/IO/importer/BaseImporter.hh>
#include <OpenMesh/Core/System/omstream.hh>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <functional>
#include <iostream>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <string_view>

#include "io/openmesh_import.hpp"
#include "mesh/surfaces.hpp"

namespace lhr {

namespace {

namespace fs = std::filesystem;

// Reflectance must stay below 1 (DESIGN §3); 8-bit white in a coloured
// PLY/OFF maps to this instead of to 1.
constexpr double kMaxColourReflectance = 0.99;
constexpr double kDefaultGrey = 0.5;

// ---------------------------------------------------------------- text helpers

std::string one_line(std::string s) {
  for (char& c : s) {
    if (c == '\n' || c == '\r' || c == '\t') c = ' ';
  }
  while (!s.empty() && s.back() == ' ') s.pop_back();
  return s;
}

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
  return s;
}

std::string extension_of(const fs::path& path) { return lower(path.extension().string()); }

std::string show(std::string_view s) {
  constexpr std::size_t kMax = 40;
  std::string q(s.substr(0, kMax));
  if (s.size() > kMax) q += "...";
  return "'" + one_line(q) + "'";
}

std::string read_file(const fs::path& path) {
  std::error_code ec;
  if (!fs::exists(path, ec)) throw InputError(path, "file not found");
  if (fs::is_directory(path, ec)) throw InputError(path, "is a directory, not a file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, "cannot open file for reading");
  std::ostringstream ss;
  ss << in.rdbuf();
  if (in.bad()) throw InputError(path, "read error");
  return ss.str();
}

// Text formats never contain NUL or most other control bytes; finding one
// means binary data (a wrong or corrupt file), which the parsers would
// otherwise skip silently.
void require_text(const fs::path& path, std::string_view text) {
  int line = 1;
  for (unsigned char c : text) {
    if (c == '\n') {
      ++line;
    } else if (c < 32 && c != '\t' && c != '\r' && c != '\f' && c != '\v') {
      char hex[8];
      std::snprintf(hex, sizeof hex, "0x%02x", c);
      throw InputError(path, line,
                       std::string("binary data (byte ") + hex + ") in a text file; is this the right file?");
    }
  }
}

struct Line {
  int number = 0;
  std::vector<std::string_view> tokens;
};

// Splits text into whitespace-separated tokens per line; '#' starts a
// comment when strip_comments is set.
std::vector<Line> tokenize(std::string_view text, bool strip_comments) {
  std::vector<Line> lines;
  int number = 0;
  std::size_t pos = 0;
  while (pos <= text.size()) {
    std::size_t end = text.find('\n', pos);
    if (end == std::string_view::npos) end = text.size();
    std::string_view raw = text.substr(pos, end - pos);
    ++number;
    if (strip_comments) {
      const std::size_t hash = raw.find('#');
      if (hash != std::string_view::npos) raw = raw.substr(0, hash);
    }
    Line line{number, {}};
    std::size_t i = 0;
    while (i < raw.size()) {
      while (i < raw.size() && std::isspace(static_cast<unsigned char>(raw[i]))) ++i;
      std::size_t j = i;
      while (j < raw.size() && !std::isspace(static_cast<unsigned char>(raw[j]))) ++j;
      if (j > i) line.tokens.push_back(raw.substr(i, j - i));
      i = j;
    }
    if (!line.tokens.empty()) lines.push_back(std::move(line));
    if (end == text.size()) break;
    pos = end + 1;
  }
  return lines;
}

std::optional<double> parse_double(std::string_view token) {
  const std::string s(token);
  char* end = nullptr;
  const double v = std::strtod(s.c_str(), &end);
  if (s.empty() || end != s.c_str() + s.size()) return std::nullopt;
  return v;
}

std::optional<long long> parse_int(std::string_view token) {
  long long v = 0;
  const char* first = token.data();
  if (!token.empty() && token[0] == '+') ++first;
  const auto [ptr, ec] = std::from_chars(first, token.data() + token.size(), v);
  if (ec != std::errc() || ptr != token.data() + token.size() || first == token.data() + token.size()) {
    return std::nullopt;
  }
  return v;
}

// The three finite numbers at line.tokens[first ...].
Vec3 finite_xyz(const fs::path& path, const Line& line, std::size_t first, const std::string& what) {
  if (line.tokens.size() < first + 3) {
    throw InputError(path, line.number, what + " needs three coordinates x y z (truncated file?)");
  }
  Vec3 p;
  for (int k = 0; k < 3; ++k) {
    const std::string_view tok = line.tokens[first + k];
    const std::optional<double> v = parse_double(tok);
    if (!v) throw InputError(path, line.number, what + ": " + show(tok) + " is not a number");
    if (!std::isfinite(*v))
      throw InputError(path, line.number, what + ": non-finite coordinate " + show(tok));
    p[k] = *v;
  }
  return p;
}

using ErrorAt = std::function<InputError(const std::string& problem)>;

// Indices must be in range and a face must span >= 3 distinct vertices.
// Repeats of a neighbouring vertex (common in exports) are removed; any
// other repeat makes the polygon self-touching, which no mesher accepts.
std::vector<int> checked_face(const std::vector<long long>& indices, long long n_vertices,
                              const ErrorAt& error) {
  if (indices.size() < 3) {
    throw error("face has " + std::to_string(indices.size()) + " vertices (needs at least 3)");
  }
  for (long long i : indices) {
    if (i < 0 || i >= n_vertices) {
      throw error("face index " + std::to_string(i) + " out of range (" + std::to_string(n_vertices) +
                  " vertices)");
    }
  }
  std::vector<int> out;
  for (long long i : indices) {
    if (out.empty() || out.back() != i) out.push_back(static_cast<int>(i));
  }
  while (out.size() > 1 && out.front() == out.back()) out.pop_back();
  std::set<int> distinct(out.begin(), out.end());
  if (distinct.size() < 3) {
    throw error("face has " + std::to_string(distinct.size()) + " distinct vertices (needs at least 3)");
  }
  if (distinct.size() != out.size()) throw error("face visits the same vertex twice");
  return out;
}

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

class TempFile {
 public:
  TempFile(const std::string& content, const std::string& suffix) {
    std::string name = (fs::temp_directory_path() / ("lhr-load-XXXXXX" + suffix)).string();
    const int fd = ::mkstemps(name.data(), static_cast<int>(suffix.size()));
    if (fd < 0)
      throw std::runtime_error("cannot create a temporary file in " + fs::temp_directory_path().string());
    ::close(fd);
    path_ = name;
    std::ofstream out(path_, std::ios::binary);
    out << content;
    if (!out) throw std::runtime_error("cannot write temporary file " + path_.string());
  }
  ~TempFile() {
    std::error_code ec;
    fs::remove(path_, ec);
  }
  TempFile(const TempFile&) = delete;
  TempFile& operator=(const TempFile&) = delete;
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

struct Declared {
  long long vertices = 0;
  long long faces = 0;
};

const std::set<std::string_view> kPlyIntegerTypes{"char", "uchar", "short", "ushort", "int",   "uint",
                                                  "int8", "uint8", "int16", "uint16", "int32", "uint32"};
const std::set<std::string_view> kPlyTypes{"char",  "uchar",  "short",   "ushort", "int",   "uint",
                                           "float", "double", "int8",    "uint8",  "int16", "uint16",
                                           "int32", "uint32", "float32", "float64"};

struct PlyProperty {
  std::string name;
  bool is_list = false;
};

struct PlyElement {
  std::string name;
  long long count = 0;
  std::vector<PlyProperty> properties;
};

// Offset of the end_header keyword at the start of a line, or npos.
std::size_t find_end_header(const std::string& bytes) {
  const std::size_t at = bytes.find("\nend_header");
  return at == std::string::npos ? at : at + 1;
}

// The header is parsed here as well as by OpenMesh so that the element
// counts are known: OpenMesh's ASCII reader stops quietly at end of file.
std::vector<PlyElement> scan_ply(const fs::path& path, const std::string& bytes, Declared& declared) {
  const std::size_t end = find_end_header(bytes);
  const std::size_t header_size = end == std::string::npos ? std::min<std::size_t>(bytes.size(), 4096) : end;
  const std::string_view header(bytes.data(), header_size);
  if (header.substr(0, 3) != "ply") throw InputError(path, 1, "not a PLY file (it must start with 'ply')");
  require_text(path, header);
  if (end == std::string::npos) throw InputError(path, "PLY header has no end_header (truncated file?)");
  // OpenMesh's reader searches for the end_header line on its own and never
  // stops if it is not a line of its own.
  const std::string_view after = std::string_view(bytes).substr(end + 10, 2);
  if (after.empty() || (after[0] != '\n' && after != "\r\n")) {
    throw InputError(path, "PLY end_header must be followed by a line break");
  }
  const std::vector<Line> lines = tokenize(header, false);
  std::vector<PlyElement> elements;
  std::string format;
  for (const Line& line : lines) {
    const std::string_view key = line.tokens[0];
    if (key == "format") {
      if (line.tokens.size() < 2) throw InputError(path, line.number, "format line without a format");
      format = std::string(line.tokens[1]);
      if (format != "ascii" && format != "binary_little_endian" && format != "binary_big_endian") {
        throw InputError(path, line.number, "unknown PLY format " + show(format));
      }
      if (line.tokens.size() != 3 || line.tokens[2] != "1.0") {
        throw InputError(path, line.number, "unsupported PLY version (expected 'format " + format + " 1.0')");
      }
    } else if (key == "element") {
      const std::optional<long long> n = line.tokens.size() == 3 ? parse_int(line.tokens[2]) : std::nullopt;
      if (!n || *n < 0) throw InputError(path, line.number, "element line must be 'element NAME COUNT'");
      elements.push_back({std::string(line.tokens[1]), *n, {}});
    } else if (key == "property") {
      if (elements.empty()) throw InputError(path, line.number, "property before any element");
      const bool is_list = line.tokens.size() >= 2 && line.tokens[1] == "list";
      if (line.tokens.size() != (is_list ? 5u : 3u))
        throw InputError(path, line.number, "malformed property line");
      // OpenMesh's reader does not reject unknown types; it can loop on them.
      const bool types_ok = is_list
                                ? kPlyIntegerTypes.count(line.tokens[2]) && kPlyTypes.count(line.tokens[3])
                                : kPlyTypes.count(line.tokens[1]) > 0;
      if (!types_ok) throw InputError(path, line.number, "unknown PLY property type in this line");
      elements.back().properties.push_back({std::string(line.tokens.back()), is_list});
    } else if (!(key == "ply" && line.number == 1) && key != "comment" && key != "obj_info") {
      throw InputError(path, line.number, "unexpected PLY header line starting with " + show(key));
    }
  }
  if (format.empty()) throw InputError(path, "PLY header has no format line");
  const auto has = [](const PlyElement& e, std::initializer_list<std::string_view> names, bool list) {
    return std::any_of(e.properties.begin(), e.properties.end(), [&](const PlyProperty& p) {
      return p.is_list == list && std::find(names.begin(), names.end(), p.name) != names.end();
    });
  };
  for (const PlyElement& e : elements) {
    if (e.name == "vertex" && !(has(e, {"x"}, false) && has(e, {"y"}, false) && has(e, {"z"}, false))) {
      throw InputError(path, "PLY vertex element needs scalar properties x, y and z");
    }
    if (e.name == "face" && !has(e, {"vertex_indices", "vertex_index"}, true)) {
      throw InputError(path, "PLY face element needs a vertex_indices list");
    }
  }
  for (const PlyElement& e : elements) {
    if (e.name == "vertex") declared.vertices = e.count;
    if (e.name == "face") declared.faces = e.count;
  }
  if (format != "ascii") return {};
  return elements;
}

// ASCII PLY body: one element per line in header order. Checked here, with
// line numbers, because OpenMesh's stream reads turn "nan" or a missing
// value into silent zeros.
void check_ascii_ply(const fs::path& path, const std::string& bytes, const std::vector<PlyElement>& elements,
                     const Declared& declared) {
  const std::size_t end = find_end_header(bytes);
  const std::size_t body = bytes.find('\n', end);
  const int header_lines = static_cast<int>(std::count(bytes.begin(), bytes.begin() + end, '\n')) + 1;
  const std::string_view text =
      body == std::string::npos ? std::string_view() : std::string_view(bytes).substr(body + 1);
  require_text(path, text);
  const std::vector<Line> lines = tokenize(text, false);
  std::size_t next = 0;
  for (const PlyElement& e : elements) {
    for (long long i = 0; i < e.count; ++i) {
      if (next >= lines.size()) {
        throw InputError(path, "file ends after " + std::to_string(i) + " of " + std::to_string(e.count) +
                                   " " + e.name + " elements (truncated file?)");
      }
      Line line = lines[next++];
      line.number += header_lines;
      std::size_t t = 0;
      std::optional<std::vector<long long>> indices;
      for (const PlyProperty& prop : e.properties) {
        if (t >= line.tokens.size()) {
          throw InputError(path, line.number,
                           e.name + " " + std::to_string(i) + ": missing value for " + prop.name);
        }
        if (prop.is_list) {
          const std::optional<long long> n = parse_int(line.tokens[t++]);
          if (!n || *n < 0 || t + *n > line.tokens.size()) {
            throw InputError(path, line.number,
                             e.name + " " + std::to_string(i) + ": list " + prop.name +
                                 " is incomplete (truncated file?)");
          }
          std::vector<long long> values;
          for (long long k = 0; k < *n; ++k) {
            const std::optional<long long> v = parse_int(line.tokens[t++]);
            if (!v)
              throw InputError(path, line.number,
                               e.name + " " + std::to_string(i) + ": bad index in " + prop.name);
            values.push_back(*v);
          }
          if (e.name == "face" && (prop.name == "vertex_indices" || prop.name == "vertex_index"))
            indices = values;
          continue;
        }
        const std::string_view tok = line.tokens[t++];
        const std::optional<double> v = parse_double(tok);
        if (!v)
          throw InputError(path, line.number,
                           e.name + " " + std::to_string(i) + ": " + show(tok) + " is not a number");
        if (e.name == "vertex" && (prop.name == "x" || prop.name == "y" || prop.name == "z")) {
          if (!std::isfinite(*v)) {
            throw InputError(path, line.number,
                             "vertex " + std::to_string(i) + ": non-finite coordinate " + show(tok));
          }
        }
      }
      // OpenMesh reads ASCII PLY as one stream of values, so an extra value
      // would shift every later element.
      if (t != line.tokens.size()) {
        throw InputError(path, line.number,
                         e.name + " " + std::to_string(i) + ": " + std::to_string(line.tokens.size()) +
                             " values where the header declares " + std::to_string(t));
      }
      if (e.name == "face") {
        if (!indices) throw InputError(path, line.number, "face element has no vertex_indices list");
        checked_face(*indices, declared.vertices, [&](const std::string& problem) {
          return InputError(path, line.number, "face " + std::to_string(i) + ": " + problem);
        });
      }
    }
  }
}

// ASCII OFF, returned with comments removed so OpenMesh's reader (which does
// not understand them) sees plain data. The header is rewritten to COFF so
// that optional per-face colours, legal after the indices of any OFF face,
// are read instead of being taken for the next face's vertex count.
std::string check_ascii_off(const fs::path& path, const std::string& text, Declared& declared) {
  require_text(path, text);
  const std::vector<Line> lines = tokenize(text, true);
  if (lines.empty()) throw InputError(path, "empty file");
  std::size_t next = 0;
  const Line& head = lines[next++];
  std::string magic(head.tokens[0]);
  if (magic.size() < 3 || magic.substr(magic.size() - 3) != "OFF") {
    throw InputError(path, head.number, "not an OFF file (it must start with 'OFF')");
  }
  std::string flags = magic.substr(0, magic.size() - 3);
  if (flags.find('4') != std::string::npos || flags.find('n') != std::string::npos) {
    throw InputError(path, head.number, show(magic) + " (homogeneous or n-dimensional OFF) is not supported");
  }
  std::vector<std::string_view> counts(head.tokens.begin() + 1, head.tokens.end());
  int counts_line = head.number;
  if (counts.empty()) {
    if (next >= lines.size()) throw InputError(path, "file ends after the OFF header (truncated file?)");
    counts = lines[next].tokens;
    counts_line = lines[next++].number;
  }
  const std::optional<long long> nv = counts.size() >= 2 ? parse_int(counts[0]) : std::nullopt;
  const std::optional<long long> nf = counts.size() >= 2 ? parse_int(counts[1]) : std::nullopt;
  if (!nv || !nf || *nv < 0 || *nf < 0) {
    throw InputError(path, counts_line, "OFF counts line must be 'VERTICES FACES EDGES'");
  }
  declared = {*nv, *nf};
  std::ostringstream clean;
  if (flags.find('C') == std::string::npos)
    flags.insert(flags.find("N") == std::string::npos ? flags.size() : flags.find('N'), "C");
  clean << flags << "OFF\n" << *nv << ' ' << *nf << " 0\n";
  for (long long i = 0; i < *nv; ++i) {
    if (next >= lines.size()) {
      throw InputError(path, "file ends after " + std::to_string(i) + " of " + std::to_string(*nv) +
                                 " vertices (truncated file?)");
    }
    const Line& line = lines[next++];
    finite_xyz(path, line, 0, "vertex " + std::to_string(i));
    for (std::string_view t : line.tokens) clean << t << ' ';
    clean << '\n';
  }
  for (long long i = 0; i < *nf; ++i) {
    if (next >= lines.size()) {
      throw InputError(path, "file ends after " + std::to_string(i) + " of " + std::to_string(*nf) +
                                 " faces (truncated file?)");
    }
    const Line& line = lines[next++];
    const ErrorAt error = [&](const std::string& problem) {
      return InputError(path, line.number, "face " + std::to_string(i) + ": " + problem);
    };
    const std::optional<long long> n = parse_int(line.tokens[0]);
    if (!n || *n < 0 || static_cast<std::size_t>(*n) + 1 > line.tokens.size()) {
      throw error("line must be 'N i1 ... iN [colour]'");
    }
    std::vector<long long> indices;
    for (long long k = 1; k <= *n; ++k) {
      const std::optional<long long> v = parse_int(line.tokens[k]);
      if (!v) throw error(show(line.tokens[k]) + " is not a vertex index");
      indices.push_back(*v);
    }
    checked_face(indices, *nv, error);
    for (std::string_view t : line.tokens) clean << t << ' ';
    clean << '\n';
  }
  return clean.str();
}

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

PolygonSoup load_openmesh(const fs::path& path, const std::string& ext) {
  const std::string bytes = read_file(path);
  if (bytes.empty()) throw InputError(path, "empty file");
  Declared declared;
  // Every face is kept as read and checked below: OpenMesh's own importer
  // would drop non-manifold faces and could not hold out-of-range indices.
  PlainImporter importer;
  OpenMesh::IO::Options options;
  options += OpenMesh::IO::Options::VertexColor;
  options += OpenMesh::IO::Options::FaceColor;
  bool ok = false;
  if (ext == ".ply") {
    const std::vector<PlyElement> ascii = scan_ply(path, bytes, declared);
    if (!ascii.empty()) check_ascii_ply(path, bytes, ascii, declared);
    QuietOpenMesh quiet;
    std::istringstream in(bytes);
    ok = OpenMesh::IO::IOManager().read(in, "ply", importer, options);
  } else {
    std::string data = bytes;
    const std::size_t first_newline = bytes.find('\n');
    const std::string first_line = bytes.substr(0, first_newline);
    if (first_line.find("BINARY") == std::string::npos || first_newline == std::string::npos) {
      data = check_ascii_off(path, bytes, declared);
    } else {
      std::uint32_t n[3] = {0, 0, 0};
      const std::size_t body = first_newline + 1 + sizeof n;
      if (bytes.size() < body)
        throw InputError(path, "file ends inside the binary OFF header (truncated file?)");
      std::memcpy(n, bytes.data() + first_newline + 1, sizeof n);
      declared = {n[0], n[1]};
      // OpenMesh's binary OFF reader does not stop at end of file; a vertex
      // takes at least 12 bytes and a face at least 16 (a triangle).
      if (12.0 * n[0] + 16.0 * n[1] > static_cast<double>(bytes.size() - body)) {
        throw InputError(path, "file is too short for the " + std::to_string(n[0]) + " vertices and " +
                                   std::to_string(n[1]) + " faces it declares (truncated file?)");
      }
    }
    // OpenMesh's OFF reader learns the header flags (colours, binary) only
    // when it opens a file by name; its stream entry point skips that step.
    const TempFile temp(data, ".off");
    QuietOpenMesh quiet;
    ok = OpenMesh::IO::IOManager().read(temp.path().string(), importer, options);
  }
  if (!ok) throw InputError(path, "cannot read this " + ext.substr(1) + " file (corrupt or truncated?)");
  if (static_cast<long long>(importer.points.size()) != declared.vertices ||
      static_cast<long long>(importer.faces.size()) != declared.faces) {
    throw InputError(path, "file declares " + std::to_string(declared.vertices) + " vertices and " +
                               std::to_string(declared.faces) + " faces but holds " +
                               std::to_string(importer.points.size()) + " and " +
                               std::to_string(importer.faces.size()) + " (truncated file?)");
  }

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
  if (ext == ".ply" || ext == ".off") return load_openmesh(path, ext);
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
  scene.camera = camera ? *camera : framing_camera(scene);
  return result;
}

}  // namespace lhr
