#include "io/ply_reader.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <map>
#include <optional>
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

// What a property contributes to the mesh; channel says which coordinate,
// colour component or radiance channel.
enum class Role { kNone, kCoordinate, kColour, kIndices, kRadiance, kStderr };

struct PlyProperty {
  std::string name;
  bool is_list = false;
  PlyType length;  // lists only
  PlyType value;   // the scalar, or each list item
  Role role = Role::kNone;
  int channel = 0;
};

struct PlyElement {
  std::string name;
  long long count = 0;
  std::vector<PlyProperty> properties;
  bool coloured = false;  // has a red, green, blue or alpha property
};

struct PlyHeader {
  std::string format;
  std::vector<PlyElement> elements;
  std::size_t end = 0;   // offset of the end_header keyword
  std::size_t body = 0;  // offset of the first byte after the end_header line
  // Headers lhr has never read: a first line other than "ply", a format
  // line that is not the second, a list length other than uchar, uint8,
  // uint16 or int. They are reported once the data has been checked.
  bool unsupported = false;
};

// The property's part in the mesh, by the names of docs/design.md §3 output
// and the usual PLY colour names.
void assign_role(const std::string& element, PlyProperty& p) {
  const auto set = [&](Role role, int channel) {
    p.role = role;
    p.channel = channel;
  };
  if (element == "face") {
    if (p.is_list && (p.name == "vertex_indices" || p.name == "vertex_index")) set(Role::kIndices, 0);
    if (p.is_list) return;
    if (p.name == "red") set(Role::kColour, 0);
    if (p.name == "green") set(Role::kColour, 1);
    if (p.name == "blue") set(Role::kColour, 2);
    if (p.name == "alpha") set(Role::kColour, 3);
    return;
  }
  if (element != "vertex" || p.is_list) return;
  if (p.name == "x" || p.name == "y" || p.name == "z") set(Role::kCoordinate, p.name[0] - 'x');
  if (p.name == "red" || p.name == "diffuse_red") set(Role::kColour, 0);
  if (p.name == "green" || p.name == "diffuse_green") set(Role::kColour, 1);
  if (p.name == "blue" || p.name == "diffuse_blue") set(Role::kColour, 2);
  if (p.name == "alpha") set(Role::kColour, 3);
  if (p.value.integer) return;
  if (p.name == "radiance_r") set(Role::kRadiance, 0);
  if (p.name == "radiance_g") set(Role::kRadiance, 1);
  if (p.name == "radiance_b") set(Role::kRadiance, 2);
  if (p.name == "radiance_stderr") set(Role::kStderr, 0);
}

bool is_list_length(std::string_view type) {
  return type == "uchar" || type == "uint8" || type == "uint16" || type == "int";
}

// The header: element counts, types and where the data starts, each line
// checked so that nothing after it has to trust the file.
PlyHeader scan_ply(const fs::path& path, const std::string& bytes) {
  PlyHeader ply;
  const std::size_t at = bytes.find("\nend_header");
  ply.end = at == std::string::npos ? at : at + 1;
  const std::size_t header_size = at == std::string::npos ? std::min<std::size_t>(bytes.size(), 4096) : ply.end;
  const std::string_view header(bytes.data(), header_size);
  if (header.substr(0, 3) != "ply") throw InputError(path, 1, "not a valid PLY file (it must start with 'ply')");
  text::require_text(path, header);
  if (at == std::string::npos) throw InputError(path, "PLY header has no end_header (truncated file?)");
  const std::string_view after = std::string_view(bytes).substr(ply.end + 10, 2);
  if (after.empty() || (after[0] != '\n' && after != "\r\n")) {
    throw InputError(path, "PLY end_header must be followed by a line break");
  }
  ply.body = ply.end + 10 + (after[0] == '\n' ? 1 : 2);
  const std::vector<Line> lines = text::tokenize(header, false);
  for (std::size_t k = 0; k < lines.size(); ++k) {
    const Line& line = lines[k];
    const std::string_view key = line.tokens[0];
    if (k == 0 && (line.number != 1 || line.tokens.size() != 1)) ply.unsupported = true;
    if (k == 1 && key != "format") ply.unsupported = true;
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
      PlyProperty p{std::string(line.tokens.back()), is_list, {}, {}};
      const auto length = kPlyTypes.find(line.tokens[is_list ? 2 : 1]);
      const auto value = kPlyTypes.find(line.tokens[is_list ? 3 : 1]);
      if (value == kPlyTypes.end() || length == kPlyTypes.end() || (is_list && !length->second.integer)) {
        throw InputError(path, line.number, "unknown PLY property type in this line");
      }
      if (is_list && !is_list_length(line.tokens[2])) ply.unsupported = true;
      p.length = length->second;
      p.value = value->second;
      PlyElement& element = ply.elements.back();
      assign_role(element.name, p);
      element.coloured |= p.role == Role::kColour;
      element.properties.push_back(p);
    } else if (key == "obj_info") {
      // Other readers take an obj_info line word by word, so a header
      // keyword in it would be read as a header line of its own.
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
  int coordinates = 0;
  for (const PlyElement& e : ply.elements) {
    // An element without properties takes no bytes, so its count is unbounded.
    if (e.count > 0 && e.properties.empty()) {
      throw InputError(path, "PLY element " + show(e.name) + " has no properties");
    }
    if (e.name == "vertex" && !(has(e, "x") && has(e, "y") && has(e, "z"))) {
      throw InputError(path, "PLY vertex element needs scalar properties x, y and z");
    }
    if (e.name == "face" && std::none_of(e.properties.begin(), e.properties.end(),
                                         [](const PlyProperty& p) { return p.role == Role::kIndices; })) {
      throw InputError(path, "PLY face element needs a vertex_indices list");
    }
    for (const PlyProperty& p : e.properties) coordinates += p.role == Role::kCoordinate;
  }
  // An ASCII file gives no other sign of a repeated coordinate.
  if (ply.format == "ascii" && coordinates != 3) ply.unsupported = true;
  return ply;
}

// What a file's elements build. Only the elements up to the first face
// element count: a vertex element after it is checked but not kept, and
// finish() then reports that the file does not hold what it declares.
class PlyBuilder {
 public:
  PlyBuilder(const PlyHeader& ply, std::size_t bytes) {
    for (const PlyElement& e : ply.elements) {
      if (e.name == "vertex") declared_vertices_ = e.count;
      if (e.name == "face") declared_faces_ = e.count;
      for (const PlyProperty& p : e.properties) {
        if (p.role == Role::kRadiance) radiance_channels_[p.channel] = true;
        if (p.role == Role::kStderr) has_stderr_ = true;
      }
    }
    has_radiance_ = radiance_channels_[0] && radiance_channels_[1] && radiance_channels_[2];
    // Every element takes at least a byte, so this bounds what a header can ask for.
    mesh_.points.reserve(static_cast<std::size_t>(std::min<long long>(declared_vertices_, bytes)));
    mesh_.faces.reserve(static_cast<std::size_t>(std::min<long long>(declared_faces_, bytes)));
  }
  long long declared_vertices() const { return declared_vertices_; }

  // One element's values, in property order, between begin and end.
  void begin(const PlyElement& e) {
    vertex_ = building_ && e.name == "vertex";
    face_ = building_ && e.name == "face";
    point_ = Vec3(0, 0, 0);
    colour_ = {0, 0, 0};
    radiance_ = Rgb(0, 0, 0);
    stderr_ = 0;
    indices_.clear();
  }
  // value: for a float property exactly a float (so narrowing it is exact).
  void scalar(const PlyProperty& p, double value) {
    if (!vertex_ && !face_) return;
    switch (p.role) {
      case Role::kCoordinate:
        point_[p.channel] = value;
        break;
      case Role::kColour:
        if (p.channel < 3) colour_[p.channel] = colour_byte(value, p.value);
        break;
      case Role::kRadiance:
        radiance_[p.channel] = value;
        break;
      case Role::kStderr:
        stderr_ = value;
        break;
      default:
        break;
    }
  }
  // Indices as stored, each taken as a 32-bit pattern (a uint above
  // INT_MAX reads as a negative index, which the face checks then reject).
  void index(long long v) {
    if (face_) indices_.push_back(static_cast<int>(static_cast<std::uint32_t>(v)));
  }
  void end(const PlyElement& e) {
    const Rgb colour = Rgb(colour_[0], colour_[1], colour_[2]) / 255.0;
    if (vertex_) {
      mesh_.points.push_back(point_);
      mesh_.vertex_colours.push_back(e.coloured ? std::optional<Rgb>(colour) : std::nullopt);
      if (has_radiance_) mesh_.radiance.push_back(radiance_);
      if (has_stderr_) mesh_.radiance_stderr.push_back(stderr_);
    } else if (face_) {
      mesh_.faces.push_back(indices_);
      mesh_.face_colours.push_back(e.coloured ? std::optional<Rgb>(colour) : std::nullopt);
    }
  }
  // After the last of an element's entries.
  void end_all(const PlyElement& e) {
    if (e.name == "face") building_ = false;
  }

  StoredMesh finish(const fs::path& path, const PlyHeader& ply) {
    if (ply.unsupported) throw InputError(path, "not a valid PLY file (corrupt or truncated?)");
    if (static_cast<long long>(mesh_.points.size()) != declared_vertices_ ||
        static_cast<long long>(mesh_.faces.size()) != declared_faces_) {
      throw InputError(path, "file declares " + std::to_string(declared_vertices_) + " vertices and " +
                                 std::to_string(declared_faces_) + " faces but holds " +
                                 std::to_string(mesh_.points.size()) + " and " +
                                 std::to_string(mesh_.faces.size()) + " (truncated file?)");
    }
    return std::move(mesh_);
  }

 private:
  // A colour component as 8 bits: an integer taken modulo 256, a float or
  // double (in [0, 1]) scaled by 255 and truncated, so PLY colours read as
  // they always have.
  static int colour_byte(double value, const PlyType& type) {
    if (type.integer) return static_cast<int>(static_cast<long long>(value) & 0xff);
    const double scaled = type.size == 4 ? static_cast<double>(static_cast<float>(value) * 255.0f) : value * 255.0;
    if (!(scaled > -2147483648.0 && scaled < 2147483648.0)) return 0;
    return static_cast<unsigned char>(static_cast<int>(scaled));
  }

  StoredMesh mesh_;
  long long declared_vertices_ = 0, declared_faces_ = 0;
  bool radiance_channels_[3] = {false, false, false};
  bool has_radiance_ = false;  // all three channels
  bool has_stderr_ = false;
  bool building_ = true;
  bool vertex_ = false, face_ = false;
  Vec3 point_;
  std::array<int, 3> colour_{};
  Rgb radiance_;
  double stderr_ = 0;
  std::vector<int> indices_;
};

// One ASCII value of the given type; integers must fit it.
std::optional<double> ascii_value(std::string_view token, const PlyType& type) {
  if (!type.integer) return parse_double(token);
  const std::optional<long long> v = parse_int(token);
  if (!v || *v < type.min || *v > type.max) return std::nullopt;
  return static_cast<double>(*v);
}

// A float property's value as a float reader rounds it (once, from the
// text, not through a double).
double as_stored(std::string_view token, double value, const PlyType& type) {
  if (type.integer || type.size != 4) return value;
  return std::strtof(std::string(token).c_str(), nullptr);
}

// ASCII PLY body: one element per line in header order, with line numbers.
void read_ascii_ply(const fs::path& path, const std::string& bytes, const PlyHeader& ply, FaceIndices faces,
                    const std::function<void()>& checkpoint, PlyBuilder& out) {
  const int header_lines = static_cast<int>(std::count(bytes.begin(), bytes.begin() + ply.end, '\n')) + 1;
  const std::string_view text = std::string_view(bytes).substr(std::min(ply.body, bytes.size()));
  text::require_text(path, text, checkpoint);
  // One line at a time: the tokens of a whole large file would double its
  // memory beside the mesh being built.
  text::LineReader lines(text, false);
  Line line;
  for (const PlyElement& e : ply.elements) {
    for (long long i = 0; i < e.count; ++i) {
      if (checkpoint && i % text::kItemsPerCheckpoint == 0) checkpoint();
      if (!lines.next(line)) {
        throw InputError(path, "file ends after " + std::to_string(i) + " of " + std::to_string(e.count) + " " +
                                   e.name + " elements (truncated file?)");
      }
      const int number = line.number + header_lines;
      // Built only for a message: most elements never need it.
      const auto where = [&] { return e.name + " " + std::to_string(i) + ": "; };
      std::size_t t = 0;
      std::optional<std::vector<long long>> indices;
      out.begin(e);
      for (const PlyProperty& prop : e.properties) {
        if (t >= line.tokens.size()) throw InputError(path, number, where() + "missing value for " + prop.name);
        if (prop.is_list) {
          const std::optional<double> n = ascii_value(line.tokens[t++], prop.length);
          if (!n || *n < 0 || t + static_cast<std::size_t>(*n) > line.tokens.size()) {
            throw InputError(path, number, where() + "list " + prop.name + " is incomplete (truncated file?)");
          }
          std::vector<long long> values;
          for (long long k = 0; k < static_cast<long long>(*n); ++k) {
            const std::string_view tok = line.tokens[t++];
            if (!ascii_value(tok, prop.value)) {
              throw InputError(path, number, where() + show(tok) + " in " + prop.name + " is not a valid value");
            }
            if (prop.role == Role::kIndices) {
              const std::optional<long long> v = parse_int(tok);
              if (!v) throw InputError(path, number, where() + "bad index in " + prop.name);
              values.push_back(*v);
            }
          }
          if (prop.role == Role::kIndices) indices = values;
          continue;
        }
        const std::string_view tok = line.tokens[t++];
        const std::optional<double> v = ascii_value(tok, prop.value);
        if (!v) {
          throw InputError(path, number,
                           where() + show(tok) + (prop.value.integer ? " is not an integer of the declared type"
                                                                   : " is not a number"));
        }
        if (prop.role == Role::kCoordinate && !std::isfinite(*v)) {
          throw InputError(path, number, "vertex " + std::to_string(i) + ": non-finite coordinate " + show(tok));
        }
        // Coordinates keep every digit written (docs/scene-format.md).
        out.scalar(prop, prop.role == Role::kCoordinate ? *v : as_stored(tok, *v, prop.value));
      }
      // Values are read per line, but a line with an extra value is more
      // likely a header that does not describe the data than a comment.
      if (t != line.tokens.size()) {
        throw InputError(path, number,
                         where() + std::to_string(line.tokens.size()) + " values where the header declares " +
                             std::to_string(t));
      }
      if (indices) {
        const ErrorAt error = [&](const std::string& problem) {
          return InputError(path, number, "face " + std::to_string(i) + ": " + problem);
        };
        if (faces == FaceIndices::kInRange) {
          text::checked_face(*indices, out.declared_vertices(), error);
        } else if (indices->empty()) {
          throw error("no vertex indices");
        } else if (std::any_of(indices->begin(), indices->end(), [](long long v) { return v > kMaxVertexIndex; })) {
          throw error("vertex index too large");
        }
        for (long long v : *indices) out.index(v);
      }
      out.end(e);
    }
    out.end_all(e);
  }
}

// Binary PLY body: walked element by element so that a count or list
// length the data cannot hold stops here, before anything is sized by it.
void read_binary_ply(const fs::path& path, const std::string& bytes, const PlyHeader& ply, FaceIndices faces,
                     const std::function<void()>& checkpoint, PlyBuilder& out) {
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
  // A value as stored: an integer or a float widened exactly, a double kept whole.
  const auto read_value = [&](const PlyType& type) {
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
      if (checkpoint && i % text::kItemsPerCheckpoint == 0) checkpoint();
      const auto where = [&] { return e.name + " " + std::to_string(i); };
      out.begin(e);
      for (const PlyProperty& prop : e.properties) {
        const std::size_t left = bytes.size() - at;
        const std::size_t head = prop.is_list ? prop.length.size : prop.value.size;
        if (left < head) {
          throw InputError(path, "file ends inside " + where() + " of " + std::to_string(e.count) +
                                     " (truncated file?)");
        }
        if (!prop.is_list) {
          if (prop.role == Role::kNone) {
            at += head;
          } else {
            out.scalar(prop, read_value(prop.value));
          }
          continue;
        }
        const long long n = read_integer(prop.length);
        if (n < 0) throw InputError(path, where() + ": negative length of list " + prop.name);
        if (static_cast<unsigned long long>(n) * prop.value.size > bytes.size() - at) {
          throw InputError(path, where() + ": list " + prop.name + " of " + std::to_string(n) +
                                     " values runs past the end of the file (truncated file?)");
        }
        if (prop.role != Role::kIndices) {
          at += n * prop.value.size;
          continue;
        }
        if (n == 0) throw InputError(path, "face " + std::to_string(i) + ": no vertex indices");
        if (!prop.value.integer) {
          throw InputError(path, "face " + std::to_string(i) + ": vertex indices of a floating-point type");
        }
        for (long long k = 0; k < n; ++k) {
          const long long v = read_integer(prop.value);
          if (faces == FaceIndices::kAsStored && v > kMaxVertexIndex) {
            throw InputError(path, "face " + std::to_string(i) + ": vertex index too large");
          }
          out.index(v);
        }
      }
      out.end(e);
    }
    out.end_all(e);
  }
}

}  // namespace

StoredMesh read_ply(const fs::path& path, const std::string& bytes, FaceIndices faces,
                    const std::function<void()>& checkpoint) {
  const PlyHeader ply = scan_ply(path, bytes);
  PlyBuilder out(ply, bytes.size());
  if (ply.format == "ascii") {
    read_ascii_ply(path, bytes, ply, faces, checkpoint, out);
  } else {
    read_binary_ply(path, bytes, ply, faces, checkpoint, out);
  }
  return out.finish(path, ply);
}

}  // namespace lhr
