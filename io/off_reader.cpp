#include "io/off_reader.hpp"

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstring>
#include <functional>
#include <optional>
#include <string_view>
#include <vector>

#include "io/input_error.hpp"
#include "io/text_scan.hpp"

namespace lhr {

namespace {

namespace fs = std::filesystem;
using text::parse_double;
using text::parse_int;
using text::Line;
using text::show;


// The colour components of one vertex or face, still as text (views into
// the file, which outlives the read).
struct ColourTokens {
  int line = 0;
  std::size_t count = 0;  // 0 (no colour), 3 or 4
  std::array<std::string_view, 4> tokens;
};

// Geomview's OFF allows 3 or 4 components (RGB or RGBA, alpha ignored),
// either integers in 0..255 or floats in 0..1, decided per face colour as
// the specification says. Vertex colours are decided per file: a file whose
// colours are written with a decimal point or an exponent anywhere is read
// as floats throughout, so a float file's "1 0 0" is red, not near-black.
bool written_as_float(const ColourTokens& c) {
  return std::any_of(c.tokens.begin(), c.tokens.begin() + c.count, [](std::string_view t) { return !parse_int(t); });
}

// what: "vertex 3", "face 0", built only for a message.
Rgb decode_colour(const fs::path& path, const ColourTokens& c, bool floats, const std::function<std::string()>& what) {
  Rgb rgb;
  for (std::size_t k = 0; k < c.count; ++k) {
    const std::optional<double> v = parse_double(c.tokens[k]);
    const bool ok = v && (floats ? (*v >= 0.0 && *v <= 1.0) : (*v >= 0.0 && *v <= 255.0));
    if (!ok) {
      throw InputError(path, c.line,
                       what() + ": colour component " + show(c.tokens[k]) +
                           (floats ? " is not a number in [0, 1] (colours with a decimal point are floats)"
                                   : " is not an integer in 0..255"));
    }
    if (k < 3) rgb[k] = floats ? *v : *v / 255.0;
  }
  return rgb;
}

// ASCII OFF, with '#' comments: coordinates as written (not narrowed to
// float), normals, texture coordinates and colours checked per line. Read
// one line at a time: the tokens of every line at once took more memory
// than the mesh they build. Only the vertex colours wait, as views, for
// the end of the vertex list, since their scale is decided per file.
StoredMesh read_ascii_off(const fs::path& path, const std::string& text, FaceIndices faces,
                          const std::function<void()>& checkpoint) {
  text::require_text(path, text, checkpoint);
  text::LineReader lines(text, true);
  Line head;
  if (!lines.next(head)) throw InputError(path, "empty file");
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
  Line counts_line = head;
  counts_line.tokens.erase(counts_line.tokens.begin());
  if (counts_line.tokens.empty() && !lines.next(counts_line)) {
    throw InputError(path, "file ends after the OFF header (truncated file?)");
  }
  const std::vector<std::string_view>& counts = counts_line.tokens;
  const std::optional<long long> nv = counts.size() >= 2 ? parse_int(counts[0]) : std::nullopt;
  const std::optional<long long> nf = counts.size() >= 2 ? parse_int(counts[1]) : std::nullopt;
  if (!nv || !nf || *nv < 0 || *nf < 0) {
    throw InputError(path, counts_line.number, "OFF counts line must be 'VERTICES FACES EDGES'");
  }
  // Each vertex and face is a line of its own, so the counts are bounded
  // by the lines left in the file before anything is sized by them.
  const std::size_t counts_end = static_cast<std::size_t>(counts_line.tokens.back().data() - text.data());
  const auto left = static_cast<long long>(std::count(text.begin() + counts_end, text.end(), '\n'));
  if (*nv > left || *nf > left - *nv) {
    throw InputError(path, counts_line.number,
                     "header declares " + std::to_string(*nv) + " vertices and " + std::to_string(*nf) +
                         " faces, but at most " + std::to_string(left) + " lines follow (truncated file?)");
  }
  const auto ends_after = [&](long long done, long long of, const char* what) {
    return InputError(path, "file ends after " + std::to_string(done) + " of " + std::to_string(of) + " " + what +
                                " (truncated file?)");
  };
  StoredMesh mesh;
  mesh.points.reserve(static_cast<std::size_t>(*nv));
  mesh.faces.reserve(static_cast<std::size_t>(*nf));
  // A vertex is x y z, then a normal, a colour and a texture coordinate, in
  // that order, as the header's N, C and ST prefixes declare.
  const std::size_t fixed = 3 + (normals ? 3 : 0) + (texcoords ? 2 : 0);
  std::vector<ColourTokens> vertex_colours;
  Line line;
  for (long long i = 0; i < *nv; ++i) {
    if (checkpoint && i % text::kItemsPerCheckpoint == 0) checkpoint();
    if (!lines.next(line)) throw ends_after(i, *nv, "vertices");
    const auto what = [i] { return "vertex " + std::to_string(i); };
    mesh.points.push_back(text::finite_xyz(path, line, 0, what()));
    const std::size_t n = line.tokens.size();
    const std::size_t colour = n >= fixed ? n - fixed : 0;
    // Without a C prefix, three or four extra values are still a colour:
    // many writers add one without saying so.
    if (n < fixed || (coloured && colour != 3 && colour != 4) || (colour != 0 && colour != 3 && colour != 4)) {
      throw InputError(path, line.number,
                       what() + ": " + std::to_string(n) + " values; " + show(magic) + " needs " +
                           std::to_string(fixed) + (coloured ? " plus 3 or 4 colour components" : "") +
                           " (x y z" + (normals ? ", a normal" : "") + (coloured ? ", a colour" : "") +
                           (texcoords ? ", s t" : "") + ")");
    }
    for (std::size_t k = 3; k < n; ++k) {
      if (!parse_double(line.tokens[k])) {
        throw InputError(path, line.number, what() + ": " + show(line.tokens[k]) + " is not a number");
      }
    }
    if (colour == 0) continue;
    if (vertex_colours.empty()) vertex_colours.resize(static_cast<std::size_t>(*nv));
    ColourTokens& c = vertex_colours[static_cast<std::size_t>(i)];
    c.line = line.number;
    c.count = colour;
    std::copy_n(line.tokens.begin() + 3 + (normals ? 3 : 0), colour, c.tokens.begin());
  }
  mesh.face_colours.reserve(static_cast<std::size_t>(*nf));
  std::vector<long long> indices;
  for (long long i = 0; i < *nf; ++i) {
    if (checkpoint && i % text::kItemsPerCheckpoint == 0) checkpoint();
    if (!lines.next(line)) throw ends_after(i, *nf, "faces");
    const text::ErrorAt error = [&](const std::string& problem) {
      return InputError(path, line.number, "face " + std::to_string(i) + ": " + problem);
    };
    const std::optional<long long> n = parse_int(line.tokens[0]);
    if (!n || *n < 0 || static_cast<std::size_t>(*n) + 1 > line.tokens.size()) {
      throw error("line must be 'N i1 ... iN [colour]'");
    }
    indices.clear();
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
                           [](long long v) { return v < -kMaxVertexIndex || v > kMaxVertexIndex; })) {
      throw error("vertex index out of the range of int");
    }
    // The colour runs to the end of the line: nothing, a colour-map index
    // (no colour map is read, so the face keeps its vertices' colour), or
    // 3 or 4 components.
    const std::size_t extra = line.tokens.size() - 1 - static_cast<std::size_t>(*n);
    if (extra == 2 || extra > 4) {
      throw error(std::to_string(extra) +
                  " values after the indices; a face colour is 1 (a colour-map index), 3 or 4 numbers");
    }
    if (extra == 1 && !parse_int(line.tokens.back())) {
      throw error(show(line.tokens.back()) + " is not a colour-map index");
    }
    std::optional<Rgb> face_colour;
    if (extra >= 3) {
      ColourTokens c{line.number, extra, {}};
      std::copy_n(line.tokens.end() - static_cast<std::ptrdiff_t>(extra), extra, c.tokens.begin());
      face_colour = decode_colour(path, c, written_as_float(c), [i] { return "face " + std::to_string(i); });
    }
    mesh.face_colours.push_back(face_colour);
    mesh.faces.emplace_back(indices.begin(), indices.end());
  }
  mesh.vertex_colours.resize(static_cast<std::size_t>(*nv));
  const bool floats = std::any_of(vertex_colours.begin(), vertex_colours.end(), written_as_float);
  for (std::size_t i = 0; i < vertex_colours.size(); ++i) {
    if (vertex_colours[i].count == 0) continue;
    mesh.vertex_colours[i] =
        decode_colour(path, vertex_colours[i], floats, [i] { return "vertex " + std::to_string(i); });
  }
  return mesh;
}

std::uint32_t little_endian_u32(const std::string& bytes, std::size_t at) {
  std::uint32_t v = 0;
  for (int b = 3; b >= 0; --b) v = (v << 8) | static_cast<unsigned char>(bytes[at + b]);
  return v;
}

float little_endian_float(const std::string& bytes, std::size_t at) {
  const std::uint32_t bits = little_endian_u32(bytes, at);
  float f = 0;
  std::memcpy(&f, &bits, sizeof f);
  return f;
}

// A binary colour: three little-endian 32-bit integers, of which the low
// byte is the 8-bit component.
Rgb binary_colour(const std::string& bytes, std::size_t at) {
  Rgb c;
  for (int k = 0; k < 3; ++k) c[k] = (little_endian_u32(bytes, at + 4 * k) & 0xff) / 255.0;
  return c;
}

// Binary OFF: a first line "[ST][C][N]OFF BINARY", then little-endian
// 32-bit counts, vertices (3 floats, then 3 for a normal, 3 ints for a
// colour, 2 floats for a texture coordinate) and faces (the length, the
// indices and, in a coloured file, 3 ints). Every count and face length is
// checked against the bytes left before it is followed.
StoredMesh read_binary_off(const fs::path& path, const std::string& bytes, FaceIndices faces,
                           const std::function<void()>& checkpoint) {
  const std::size_t newline = bytes.find('\n');
  const std::vector<text::Line> first = text::tokenize(std::string_view(bytes).substr(0, newline), false);
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
  const long long n_vertices = little_endian_u32(bytes, at);
  const long long n_faces = little_endian_u32(bytes, at + 4);
  at += 12;
  const unsigned long long vertex_bytes = 12 + (normals ? 12 : 0) + (colours ? 12 : 0) + (texcoords ? 8 : 0);
  const unsigned long long face_colour_bytes = colours ? 12 : 0;
  if (static_cast<unsigned long long>(n_vertices) * vertex_bytes > left()) {
    throw InputError(path, "file is too short for the " + std::to_string(n_vertices) +
                               " vertices it declares (truncated file?)");
  }
  StoredMesh mesh;
  mesh.points.reserve(static_cast<std::size_t>(n_vertices));
  for (long long i = 0; i < n_vertices; ++i) {
    if (checkpoint && i % text::kItemsPerCheckpoint == 0) checkpoint();
    Vec3 p;
    for (int k = 0; k < 3; ++k) p[k] = little_endian_float(bytes, at + 4 * k);
    mesh.points.push_back(p);
    const std::size_t colour = at + 12 + (normals ? 12 : 0);
    mesh.vertex_colours.push_back(colours ? std::optional<Rgb>(binary_colour(bytes, colour)) : std::nullopt);
    at += vertex_bytes;
  }
  // Each face takes at least its 4-byte length.
  mesh.faces.reserve(static_cast<std::size_t>(std::min<unsigned long long>(n_faces, left() / 4)));
  for (long long i = 0; i < n_faces; ++i) {
    if (checkpoint && i % text::kItemsPerCheckpoint == 0) checkpoint();
    if (left() < 4) {
      throw InputError(path, "file ends after " + std::to_string(i) + " of " + std::to_string(n_faces) +
                                 " faces (truncated file?)");
    }
    const unsigned long long n = little_endian_u32(bytes, at);
    at += 4;
    if (n == 0) throw InputError(path, "face " + std::to_string(i) + ": no vertex indices");
    if (4 * n + face_colour_bytes > left()) {
      throw InputError(path, "face " + std::to_string(i) + " of " + std::to_string(n) +
                                 " vertices runs past the end of the file (truncated file?)");
    }
    std::vector<int>& face = mesh.faces.emplace_back();
    face.reserve(n);
    for (unsigned long long k = 0; k < n; ++k) {
      const std::uint32_t v = little_endian_u32(bytes, at + 4 * k);
      if (faces == FaceIndices::kAsStored && v > kMaxVertexIndex) {
        throw InputError(path, "face " + std::to_string(i) + ": vertex index too large");
      }
      // Taken as a 32-bit pattern: one above INT_MAX reads as negative and
      // fails the range check of a loaded scene.
      face.push_back(static_cast<int>(v));
    }
    at += 4 * n;
    mesh.face_colours.push_back(colours ? std::optional<Rgb>(binary_colour(bytes, at)) : std::nullopt);
    at += face_colour_bytes;
  }
  return mesh;
}

}  // namespace

StoredMesh read_off(const fs::path& path, const std::string& bytes, FaceIndices faces,
                    const std::function<void()>& checkpoint) {
  const std::size_t newline = bytes.find('\n');
  const bool binary = newline != std::string::npos && bytes.substr(0, newline).find("BINARY") != std::string::npos;
  return binary ? read_binary_off(path, bytes, faces, checkpoint)
                : read_ascii_off(path, bytes, faces, checkpoint);
}

}  // namespace lhr
