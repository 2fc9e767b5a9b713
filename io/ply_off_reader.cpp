#include "io/ply_off_reader.hpp"

#include <unistd.h>
#include <OpenMesh/Core/IO/IOManager.hh>
#include <OpenMesh/Core/IO/MeshIO.hh>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <limits>
#include <map>
#include <optional>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include "io/input_error.hpp"
#include "io/text_scan.hpp"

namespace lhr {

namespace {

namespace fs = std::filesystem;
using text::ErrorAt;
using text::Line;
using text::parse_double;
using text::parse_int;
using text::show;

constexpr long long kMaxInt = std::numeric_limits<int>::max();

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

// -------------------------------------------------------------------- PLY

struct PlyType {
  int size = 0;  // bytes in a binary file
  bool integer = false;
  long long min = 0, max = 0;  // integers only
};

const std::map<std::string_view, PlyType> kPlyTypes{
    {"char", {1, true, -128, 127}},
    {"int8", {1, true, -128, 127}},
    {"uchar", {1, true, 0, 255}},
    {"uint8", {1, true, 0, 255}},
    {"short", {2, true, -32768, 32767}},
    {"int16", {2, true, -32768, 32767}},
    {"ushort", {2, true, 0, 65535}},
    {"uint16", {2, true, 0, 65535}},
    {"int", {4, true, std::numeric_limits<std::int32_t>::min(), std::numeric_limits<std::int32_t>::max()}},
    {"int32", {4, true, std::numeric_limits<std::int32_t>::min(), std::numeric_limits<std::int32_t>::max()}},
    {"uint", {4, true, 0, std::numeric_limits<std::uint32_t>::max()}},
    {"uint32", {4, true, 0, std::numeric_limits<std::uint32_t>::max()}},
    {"float", {4, false}},
    {"float32", {4, false}},
    {"double", {8, false}},
    {"float64", {8, false}},
};

struct PlyProperty {
  std::string name;
  bool is_list = false;
  PlyType length;  // lists only
  PlyType value;   // the scalar, or each list item
};

struct PlyElement {
  std::string name;
  long long count = 0;
  std::vector<PlyProperty> properties;
};

struct PlyHeader {
  std::string format;
  std::vector<PlyElement> elements;
  std::size_t end = 0;   // offset of the end_header keyword
  std::size_t body = 0;  // offset of the first byte after the end_header line
};

bool is_face_indices(const PlyElement& e, const PlyProperty& p) {
  return e.name == "face" && p.is_list && (p.name == "vertex_indices" || p.name == "vertex_index");
}

// The header is parsed here as well as by OpenMesh so that everything its
// reader trusts is known: element counts, types and where the data starts.
PlyHeader scan_ply(const fs::path& path, const std::string& bytes, Declared& declared) {
  PlyHeader ply;
  const std::size_t at = bytes.find("\nend_header");
  ply.end = at == std::string::npos ? at : at + 1;
  const std::size_t header_size = at == std::string::npos ? std::min<std::size_t>(bytes.size(), 4096) : ply.end;
  const std::string_view header(bytes.data(), header_size);
  if (header.substr(0, 3) != "ply") throw InputError(path, 1, "not a valid PLY file (it must start with 'ply')");
  text::require_text(path, header);
  if (at == std::string::npos) throw InputError(path, "PLY header has no end_header (truncated file?)");
  // OpenMesh's reader searches for the end_header line on its own and never
  // stops if it is not a line of its own.
  const std::string_view after = std::string_view(bytes).substr(ply.end + 10, 2);
  if (after.empty() || (after[0] != '\n' && after != "\r\n")) {
    throw InputError(path, "PLY end_header must be followed by a line break");
  }
  ply.body = ply.end + 10 + (after[0] == '\n' ? 1 : 2);
  for (const Line& line : text::tokenize(header, false)) {
    const std::string_view key = line.tokens[0];
    if (key == "format") {
      if (line.tokens.size() < 2) throw InputError(path, line.number, "format line without a format");
      ply.format = std::string(line.tokens[1]);
      if (ply.format != "ascii" && ply.format != "binary_little_endian" && ply.format != "binary_big_endian") {
        throw InputError(path, line.number, "unknown PLY format " + show(ply.format));
      }
      if (line.tokens.size() != 3 || line.tokens[2] != "1.0") {
        throw InputError(path, line.number, "unsupported PLY version (expected 'format " + ply.format + " 1.0')");
      }
    } else if (key == "element") {
      const std::optional<long long> n = line.tokens.size() == 3 ? parse_int(line.tokens[2]) : std::nullopt;
      if (!n || *n < 0) throw InputError(path, line.number, "element line must be 'element NAME COUNT'");
      ply.elements.push_back({std::string(line.tokens[1]), *n, {}});
    } else if (key == "property") {
      if (ply.elements.empty()) throw InputError(path, line.number, "property before any element");
      const bool is_list = line.tokens.size() >= 2 && line.tokens[1] == "list";
      if (line.tokens.size() != (is_list ? 5u : 3u))
        throw InputError(path, line.number, "malformed property line");
      // OpenMesh's reader does not reject unknown types; it can loop on them.
      PlyProperty p{std::string(line.tokens.back()), is_list, {}, {}};
      const auto length = kPlyTypes.find(line.tokens[is_list ? 2 : 1]);
      const auto value = kPlyTypes.find(line.tokens[is_list ? 3 : 1]);
      if (value == kPlyTypes.end() || length == kPlyTypes.end() || (is_list && !length->second.integer)) {
        throw InputError(path, line.number, "unknown PLY property type in this line");
      }
      p.length = length->second;
      p.value = value->second;
      ply.elements.back().properties.push_back(p);
    } else if (key == "obj_info") {
      // OpenMesh's reader takes an obj_info line word by word, so a header
      // keyword in it is read as a header line of its own (and crashes it).
      for (std::size_t i = 1; i < line.tokens.size(); ++i) {
        const std::string_view w = line.tokens[i];
        if (w == "element" || w == "property" || w == "end_header") {
          throw InputError(path, line.number, "obj_info line contains the PLY keyword " + show(w));
        }
      }
    } else if (!(key == "ply" && line.number == 1) && key != "comment") {
      throw InputError(path, line.number, "unexpected PLY header line starting with " + show(key));
    }
  }
  if (ply.format.empty()) throw InputError(path, "PLY header has no format line");
  const auto has = [](const PlyElement& e, std::string_view name) {
    return std::any_of(e.properties.begin(), e.properties.end(),
                       [&](const PlyProperty& p) { return !p.is_list && p.name == name; });
  };
  for (const PlyElement& e : ply.elements) {
    // An element without properties takes no bytes, so its count is unbounded.
    if (e.count > 0 && e.properties.empty()) {
      throw InputError(path, "PLY element " + show(e.name) + " has no properties");
    }
    if (e.name == "vertex" && !(has(e, "x") && has(e, "y") && has(e, "z"))) {
      throw InputError(path, "PLY vertex element needs scalar properties x, y and z");
    }
    if (e.name == "face" && std::none_of(e.properties.begin(), e.properties.end(),
                                         [&](const PlyProperty& p) { return is_face_indices(e, p); })) {
      throw InputError(path, "PLY face element needs a vertex_indices list");
    }
    if (e.name == "vertex") declared.vertices = e.count;
    if (e.name == "face") declared.faces = e.count;
  }
  return ply;
}

// One ASCII value of the given type; integers must fit it, as OpenMesh
// reads them into that type.
std::optional<double> ascii_value(std::string_view token, const PlyType& type) {
  if (!type.integer) return parse_double(token);
  const std::optional<long long> v = parse_int(token);
  if (!v || *v < type.min || *v > type.max) return std::nullopt;
  return static_cast<double>(*v);
}

// ASCII PLY body: one element per line in header order. Checked here, with
// line numbers, because OpenMesh's stream reads turn "nan" or a missing
// value into silent zeros.
void check_ascii_ply(const fs::path& path, const std::string& bytes, const PlyHeader& ply,
                     const Declared& declared, FaceIndices faces, std::vector<Vec3>& points) {
  const int header_lines = static_cast<int>(std::count(bytes.begin(), bytes.begin() + ply.end, '\n')) + 1;
  const std::string_view text = std::string_view(bytes).substr(std::min(ply.body, bytes.size()));
  text::require_text(path, text);
  const std::vector<Line> lines = text::tokenize(text, false);
  std::size_t next = 0;
  for (const PlyElement& e : ply.elements) {
    for (long long i = 0; i < e.count; ++i) {
      if (next >= lines.size()) {
        throw InputError(path, "file ends after " + std::to_string(i) + " of " + std::to_string(e.count) + " " +
                                   e.name + " elements (truncated file?)");
      }
      Line line = lines[next++];
      line.number += header_lines;
      const std::string where = e.name + " " + std::to_string(i) + ": ";
      std::size_t t = 0;
      std::optional<std::vector<long long>> indices;
      Vec3 point(0, 0, 0);
      for (const PlyProperty& prop : e.properties) {
        if (t >= line.tokens.size()) throw InputError(path, line.number, where + "missing value for " + prop.name);
        if (prop.is_list) {
          const std::optional<double> n = ascii_value(line.tokens[t++], prop.length);
          if (!n || *n < 0 || t + static_cast<std::size_t>(*n) > line.tokens.size()) {
            throw InputError(path, line.number, where + "list " + prop.name + " is incomplete (truncated file?)");
          }
          std::vector<long long> values;
          for (long long k = 0; k < static_cast<long long>(*n); ++k) {
            const std::string_view tok = line.tokens[t++];
            if (!ascii_value(tok, prop.value)) {
              throw InputError(path, line.number, where + show(tok) + " in " + prop.name + " is not a valid value");
            }
            if (is_face_indices(e, prop)) {
              const std::optional<long long> v = parse_int(tok);
              if (!v) throw InputError(path, line.number, where + "bad index in " + prop.name);
              values.push_back(*v);
            }
          }
          if (is_face_indices(e, prop)) indices = values;
          continue;
        }
        const std::string_view tok = line.tokens[t++];
        const std::optional<double> v = ascii_value(tok, prop.value);
        if (!v) {
          throw InputError(path, line.number,
                           where + show(tok) + (prop.value.integer ? " is not an integer of the declared type"
                                                                   : " is not a number"));
        }
        if (e.name == "vertex" && (prop.name == "x" || prop.name == "y" || prop.name == "z") &&
            !std::isfinite(*v)) {
          throw InputError(path, line.number, "vertex " + std::to_string(i) + ": non-finite coordinate " + show(tok));
        }
        if (e.name == "vertex" && prop.name.size() == 1 && prop.name[0] >= 'x' && prop.name[0] <= 'z') {
          point[prop.name[0] - 'x'] = *v;
        }
      }
      if (e.name == "vertex") points.push_back(point);
      // OpenMesh reads ASCII PLY as one stream of values, so an extra value
      // would shift every later element.
      if (t != line.tokens.size()) {
        throw InputError(path, line.number,
                         where + std::to_string(line.tokens.size()) + " values where the header declares " +
                             std::to_string(t));
      }
      if (!indices) continue;
      const ErrorAt error = [&](const std::string& problem) {
        return InputError(path, line.number, "face " + std::to_string(i) + ": " + problem);
      };
      if (faces == FaceIndices::kInRange) {
        text::checked_face(*indices, declared.vertices, error);
      } else if (indices->empty()) {
        throw error("no vertex indices");
      } else if (std::any_of(indices->begin(), indices->end(), [](long long v) { return v > kMaxInt; })) {
        throw error("vertex index too large");
      }
    }
  }
}

// Binary PLY body: walked element by element so that a count or list
// length the data cannot hold stops here, not in a reader that would loop
// on it and allocate for it.
void check_binary_ply(const fs::path& path, const std::string& bytes, const PlyHeader& ply, FaceIndices faces,
                      std::vector<Vec3>& points) {
  const bool big_endian = ply.format == "binary_big_endian";
  std::size_t at = ply.body;
  const auto read_integer = [&](const PlyType& type) {
    std::uint64_t u = 0;
    for (int b = 0; b < type.size; ++b) {
      const auto byte = static_cast<unsigned char>(bytes[at + (big_endian ? b : type.size - 1 - b)]);
      u = (u << 8) | byte;
    }
    at += type.size;
    if (type.min < 0 && type.size < 8 && (u >> (8 * type.size - 1)) != 0) {
      return static_cast<long long>(u) - (1LL << (8 * type.size));
    }
    return static_cast<long long>(u);
  };
  // A coordinate as stored: a float widened exactly, a double kept whole.
  const auto read_coordinate = [&](const PlyType& type) {
    if (type.integer) return static_cast<double>(read_integer(type));
    const std::uint64_t bits = static_cast<std::uint64_t>(read_integer(PlyType{type.size, true, 0, 0}));
    if (type.size == 4) {
      const auto narrow = static_cast<std::uint32_t>(bits);
      float f = 0;
      std::memcpy(&f, &narrow, sizeof f);
      return static_cast<double>(f);
    }
    double d = 0;
    std::memcpy(&d, &bits, sizeof d);
    return d;
  };
  for (const PlyElement& e : ply.elements) {
    for (long long i = 0; i < e.count; ++i) {
      const std::string where = e.name + " " + std::to_string(i);
      Vec3 point(0, 0, 0);
      for (const PlyProperty& prop : e.properties) {
        const std::size_t left = bytes.size() - at;
        const std::size_t head = prop.is_list ? prop.length.size : prop.value.size;
        if (left < head) {
          throw InputError(path, "file ends inside " + where + " of " + std::to_string(e.count) +
                                     " (truncated file?)");
        }
        if (!prop.is_list) {
          if (e.name == "vertex" && prop.name.size() == 1 && prop.name[0] >= 'x' && prop.name[0] <= 'z') {
            point[prop.name[0] - 'x'] = read_coordinate(prop.value);
          } else {
            at += head;
          }
          continue;
        }
        const long long n = read_integer(prop.length);
        if (n < 0) throw InputError(path, where + ": negative length of list " + prop.name);
        if (static_cast<unsigned long long>(n) * prop.value.size > bytes.size() - at) {
          throw InputError(path, where + ": list " + prop.name + " of " + std::to_string(n) +
                                     " values runs past the end of the file (truncated file?)");
        }
        if (is_face_indices(e, prop)) {
          if (n == 0) throw InputError(path, "face " + std::to_string(i) + ": no vertex indices");
          if (faces == FaceIndices::kAsStored && prop.value.integer && prop.value.max > kMaxInt) {
            for (long long k = 0; k < n; ++k) {
              if (read_integer(prop.value) > kMaxInt) {
                throw InputError(path, "face " + std::to_string(i) + ": vertex index too large");
              }
            }
            continue;
          }
        }
        at += n * prop.value.size;
      }
      if (e.name == "vertex") points.push_back(point);
    }
  }
}

// -------------------------------------------------------------------- OFF

// Coordinates and colours of an ASCII OFF, read here rather than by
// OpenMesh, whose reader narrows coordinates to float, guesses the colour
// type from the first vertex alone and reads a float COFF (components in
// [0, 1]) as black.
struct OffValues {
  std::vector<Vec3> points;
  std::vector<std::optional<Rgb>> vertices;  // colours
  std::vector<std::optional<Rgb>> faces;     // colours
};

// The colour components of one vertex or face, still as text.
struct ColourTokens {
  int line = 0;
  std::string what;  // "vertex 3", "face 0"
  std::vector<std::string_view> tokens;
};

// Geomview's OFF allows 3 or 4 components (RGB or RGBA, alpha ignored),
// either integers in 0..255 or floats in 0..1, decided per face colour as
// the specification says. Vertex colours are decided per file: a file whose
// colours are written with a decimal point or an exponent anywhere is read
// as floats throughout, so a float file's "1 0 0" is red, not near-black.
std::vector<std::optional<Rgb>> decode_colours(const fs::path& path, const std::vector<ColourTokens>& colours,
                                               std::size_t count, bool per_file) {
  const auto has_float = [](const ColourTokens& c) {
    return std::any_of(c.tokens.begin(), c.tokens.end(), [](std::string_view t) { return !parse_int(t); });
  };
  const bool file_floats = per_file && std::any_of(colours.begin(), colours.end(), has_float);
  std::vector<std::optional<Rgb>> out(count);
  for (std::size_t i = 0; i < colours.size(); ++i) {
    const ColourTokens& c = colours[i];
    if (c.tokens.empty()) continue;
    const bool floats = per_file ? file_floats : has_float(c);
    Rgb rgb;
    for (std::size_t k = 0; k < c.tokens.size(); ++k) {
      const std::optional<double> v = parse_double(c.tokens[k]);
      const bool ok = v && (floats ? (*v >= 0.0 && *v <= 1.0) : (*v >= 0.0 && *v <= 255.0));
      if (!ok) {
        throw InputError(path, c.line,
                         c.what + ": colour component " + show(c.tokens[k]) +
                             (floats ? " is not a number in [0, 1] (colours with a decimal point are floats)"
                                     : " is not an integer in 0..255"));
      }
      if (k < 3) rgb[k] = floats ? *v : *v / 255.0;
    }
    out[i] = rgb;
  }
  return out;
}

// ASCII OFF, returned as plain OFF (coordinates and vertex indices only,
// comments removed) for OpenMesh's reader, which does not understand
// comments; normals, texture coordinates and colours are checked here and
// the coordinates and colours returned in values.
std::string check_ascii_off(const fs::path& path, const std::string& text, Declared& declared, FaceIndices faces,
                            OffValues& values) {
  text::require_text(path, text);
  const std::vector<Line> lines = text::tokenize(text, true);
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
  const bool texcoords = flags.find("ST") != std::string::npos;
  const bool coloured = flags.find('C') != std::string::npos;
  const bool normals = flags.find('N') != std::string::npos;
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
  // Each vertex and face is a line of its own; the reader would otherwise
  // reserve and loop for whatever the header claims.
  const auto left = static_cast<long long>(lines.size() - next);
  if (*nv > left || *nf > left - *nv) {
    throw InputError(path, counts_line,
                     "header declares " + std::to_string(*nv) + " vertices and " + std::to_string(*nf) +
                         " faces, but only " + std::to_string(left) + " lines follow (truncated file?)");
  }
  declared = {*nv, *nf};
  std::ostringstream clean;
  clean << "OFF\n" << *nv << ' ' << *nf << " 0\n";
  // A vertex is x y z, then a normal, a colour and a texture coordinate, in
  // that order, as the header's N, C and ST prefixes declare.
  const std::size_t fixed = 3 + (normals ? 3 : 0) + (texcoords ? 2 : 0);
  std::vector<ColourTokens> vertex_colours;
  for (long long i = 0; i < *nv; ++i) {
    const Line& line = lines[next++];
    const std::string what = "vertex " + std::to_string(i);
    values.points.push_back(text::finite_xyz(path, line, 0, what));
    const std::size_t n = line.tokens.size();
    const std::size_t colour = n >= fixed ? n - fixed : 0;
    // Without a C prefix, three or four extra values are still a colour:
    // many writers add one without saying so.
    if (n < fixed || (coloured && colour != 3 && colour != 4) || (colour != 0 && colour != 3 && colour != 4)) {
      throw InputError(path, line.number,
                       what + ": " + std::to_string(n) + " values; " + show(magic) + " needs " +
                           std::to_string(fixed) + (coloured ? " plus 3 or 4 colour components" : "") +
                           " (x y z" + (normals ? ", a normal" : "") + (coloured ? ", a colour" : "") +
                           (texcoords ? ", s t" : "") + ")");
    }
    for (std::size_t k = 3; k < n; ++k) {
      if (!parse_double(line.tokens[k])) {
        throw InputError(path, line.number, what + ": " + show(line.tokens[k]) + " is not a number");
      }
    }
    const std::size_t first = 3 + (normals ? 3 : 0);
    vertex_colours.push_back({line.number, what,
                              std::vector<std::string_view>(line.tokens.begin() + first,
                                                            line.tokens.begin() + first + colour)});
    clean << line.tokens[0] << ' ' << line.tokens[1] << ' ' << line.tokens[2] << '\n';
  }
  std::vector<ColourTokens> face_colours;
  for (long long i = 0; i < *nf; ++i) {
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
    if (faces == FaceIndices::kInRange) {
      text::checked_face(indices, *nv, error);
    } else if (indices.empty()) {
      throw error("no vertex indices");
    } else if (std::any_of(indices.begin(), indices.end(),
                           [](long long v) { return v < -kMaxInt || v > kMaxInt; })) {
      throw error("vertex index out of the range of int");
    }
    // The colour runs to the end of the line: nothing, a colour-map index
    // (no colour map is read, so the face keeps its vertices' colour), or
    // 3 or 4 components.
    std::vector<std::string_view> colour(line.tokens.begin() + 1 + *n, line.tokens.end());
    if (colour.size() == 2 || colour.size() > 4) {
      throw error(std::to_string(colour.size()) +
                  " values after the indices; a face colour is 1 (a colour-map index), 3 or 4 numbers");
    }
    if (colour.size() == 1) {
      if (!parse_int(colour[0])) throw error(show(colour[0]) + " is not a colour-map index");
      colour.clear();
    }
    face_colours.push_back({line.number, "face " + std::to_string(i), colour});
    clean << *n;
    for (long long k = 1; k <= *n; ++k) clean << ' ' << line.tokens[k];
    clean << '\n';
  }
  values.vertices = decode_colours(path, vertex_colours, static_cast<std::size_t>(*nv), true);
  values.faces = decode_colours(path, face_colours, static_cast<std::size_t>(*nf), false);
  return clean.str();
}

std::uint32_t little_endian_u32(const std::string& bytes, std::size_t at) {
  std::uint32_t v = 0;
  for (int b = 3; b >= 0; --b) v = (v << 8) | static_cast<unsigned char>(bytes[at + b]);
  return v;
}

// Binary OFF: a first line "[ST][C][N]OFF BINARY", then little-endian
// 32-bit counts, vertices and faces laid out as OpenMesh's reader expects
// them (3 floats, then 3 for a normal, 3 ints for a colour, 2 floats for a
// texture coordinate; a face is its length, its indices and, in a coloured
// file, 3 ints). Walked here because that reader trusts every count and
// runs on past the end of the data. Returned with the first line in
// canonical form, so OpenMesh takes the file for binary exactly when this
// check did.
std::string check_binary_off(const fs::path& path, const std::string& bytes, Declared& declared,
                             FaceIndices faces) {
  const std::size_t newline = bytes.find('\n');
  const std::vector<Line> first = text::tokenize(std::string_view(bytes).substr(0, newline), false);
  const std::string magic = first.empty() ? std::string() : std::string(first[0].tokens[0]);
  std::string_view flags = magic;
  const bool texcoords = flags.substr(0, 2) == "ST";
  if (texcoords) flags.remove_prefix(2);
  const bool colours = flags.substr(0, 1) == "C";
  if (colours) flags.remove_prefix(1);
  const bool normals = flags.substr(0, 1) == "N";
  if (normals) flags.remove_prefix(1);
  if (first.size() != 1 || first[0].tokens.size() != 2 || first[0].tokens[1] != "BINARY" || flags != "OFF") {
    throw InputError(path, 1, "binary OFF must start with a line '[ST][C][N]OFF BINARY'");
  }
  std::size_t at = newline + 1;
  const auto left = [&] { return static_cast<unsigned long long>(bytes.size() - at); };
  if (left() < 12) throw InputError(path, "file ends inside the binary OFF header (truncated file?)");
  declared = {little_endian_u32(bytes, at), little_endian_u32(bytes, at + 4)};
  at += 12;
  const unsigned long long vertex_bytes = 12 + (normals ? 12 : 0) + (colours ? 12 : 0) + (texcoords ? 8 : 0);
  const unsigned long long face_colour_bytes = colours ? 12 : 0;
  if (static_cast<unsigned long long>(declared.vertices) * vertex_bytes > left()) {
    throw InputError(path, "file is too short for the " + std::to_string(declared.vertices) +
                               " vertices it declares (truncated file?)");
  }
  at += declared.vertices * vertex_bytes;
  for (long long i = 0; i < declared.faces; ++i) {
    if (left() < 4) {
      throw InputError(path, "file ends after " + std::to_string(i) + " of " + std::to_string(declared.faces) +
                                 " faces (truncated file?)");
    }
    const unsigned long long n = little_endian_u32(bytes, at);
    at += 4;
    if (n == 0) throw InputError(path, "face " + std::to_string(i) + ": no vertex indices");
    if (4 * n + face_colour_bytes > left()) {
      throw InputError(path, "face " + std::to_string(i) + " of " + std::to_string(n) +
                                 " vertices runs past the end of the file (truncated file?)");
    }
    if (faces == FaceIndices::kAsStored) {
      for (unsigned long long k = 0; k < n; ++k) {
        if (little_endian_u32(bytes, at + 4 * k) > kMaxInt) {
          throw InputError(path, "face " + std::to_string(i) + ": vertex index too large");
        }
      }
    }
    at += 4 * n + face_colour_bytes;
  }
  return magic + " BINARY\n" + bytes.substr(newline + 1);
}

}  // namespace

void read_ply_off(const fs::path& path, PlainImporter& importer, FaceIndices faces) {
  const std::string ext = text::extension_of(path);
  if (ext != ".ply" && ext != ".off") {
    throw InputError(path, "unknown mesh format " + show(path.extension().string()) + " (expected .ply or .off)");
  }
  const std::string format = ext == ".ply" ? "PLY" : "OFF";
  const std::string bytes = text::read_file(path);
  if (bytes.empty()) throw InputError(path, "file is empty");
  // Colours are always requested: OpenMesh's binary OFF reader skips a
  // face's colour only when asked for it, and check_binary_off assumes the
  // layout the file declares. Custom keeps extra PLY properties (radiance).
  OpenMesh::IO::Options options = OpenMesh::IO::Options::Custom;
  options += OpenMesh::IO::Options::VertexColor;
  options += OpenMesh::IO::Options::FaceColor;
  Declared declared;
  bool ok = false;
  try {
    if (ext == ".ply") {
      const PlyHeader ply = scan_ply(path, bytes, declared);
      std::vector<Vec3> points;
      if (ply.format == "ascii") {
        check_ascii_ply(path, bytes, ply, declared, faces, points);
      } else {
        check_binary_ply(path, bytes, ply, faces, points);
      }
      const QuietOpenMesh quiet;
      std::istringstream in(bytes);
      ok = OpenMesh::IO::IOManager().read(in, "ply", importer, options);
      // OpenMesh's PLY reader narrows every coordinate to float; the checks
      // above read them as the file stores them (docs/scene-format.md).
      if (ok && points.size() == importer.points.size()) importer.points = std::move(points);
    } else {
      const std::size_t newline = bytes.find('\n');
      const bool binary =
          newline != std::string::npos && bytes.substr(0, newline).find("BINARY") != std::string::npos;
      std::optional<OffValues> values;
      const std::string data = binary ? check_binary_off(path, bytes, declared, faces)
                                      : check_ascii_off(path, bytes, declared, faces, values.emplace());
      // OpenMesh's OFF reader learns the header flags (colours, binary) only
      // when it opens a file by name; its stream entry point skips that step.
      const TempFile temp(data, ".off");
      {
        const QuietOpenMesh quiet;
        ok = OpenMesh::IO::IOManager().read(temp.path().string(), importer, options);
      }
      if (ok && values && importer.points.size() == values->vertices.size() &&
          importer.faces.size() == values->faces.size()) {
        importer.points = std::move(values->points);
        importer.vertex_colours = std::move(values->vertices);
        importer.face_colours = std::move(values->faces);
      }
    }
  } catch (const ImportAborted& abort) {
    throw InputError(path, abort.problem);
  }
  if (!ok) throw InputError(path, "not a valid " + format + " file (corrupt or truncated?)");
  if (static_cast<long long>(importer.points.size()) != declared.vertices ||
      static_cast<long long>(importer.faces.size()) != declared.faces) {
    throw InputError(path, "file declares " + std::to_string(declared.vertices) + " vertices and " +
                               std::to_string(declared.faces) + " faces but holds " +
                               std::to_string(importer.points.size()) + " and " +
                               std::to_string(importer.faces.size()) + " (truncated file?)");
  }
  // A failed text parse yields faces without indices (the readers then read
  // zeros to the end), so an empty face means a malformed face list.
  if (importer.empty_faces > 0) {
    throw InputError(path, std::to_string(importer.empty_faces) +
                               " face(s) without vertex indices (malformed or truncated face list)");
  }
}

}  // namespace lhr
