// OpenMesh's colour property value-initialises VectorT<uchar,3>, whose
// default constructor leaves it unset on purpose; GCC flags the copy once
// request_vertex_colors() is instantiated here. Every colour is set below.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif

#include "io/mesh_io.hpp"


#include <OpenMesh/Core/IO/IOManager.hh>
#include <OpenMesh/Core/IO/MeshIO.hh>

#include <algorithm>
#include <cctype>
#include <fstream>
#include <iterator>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <system_error>

#include "io/atomic_file.hpp"
#include "io/input_error.hpp"
#include "io/ply_off_reader.hpp"
#include "io/quiet_openmesh.hpp"

namespace lhr {

namespace {

// docs/design.md §3: the PLY carries linear radiance beside the display colour under
// these names, so other tools show the colour and lhr can read values back.
constexpr const char* kRadianceNames[3] = {"radiance_r", "radiance_g", "radiance_b"};
constexpr const char* kStderrName = "radiance_stderr";

// Points are stored as float in PLY (OpenMesh writes float x y z); OFF is
// text, and 9 significant digits reproduce a float exactly.
constexpr std::streamsize kTextPrecision = std::numeric_limits<float>::max_digits10;

std::string lower_extension(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext;
}

// docs/design.md §3 output: what the colour and radiance properties mean, in the
// header where a reader of the file finds it.
// The PLY header says what its colour and radiance properties are; OpenMesh
// writes none, so they go in after its format line.
void add_ply_comments(std::string& bytes, const std::filesystem::path& file, const ExportMesh& mesh) {
  const std::size_t format = bytes.find("\nformat ");
  const std::size_t line_end = format == std::string::npos ? format : bytes.find('\n', format + 1);
  if (line_end == std::string::npos) throw std::runtime_error(file.string() + ": PLY header without a format line");
  std::string comments = "comment red green blue: " + mesh.colour_meaning + "\n" +
                         "comment radiance_r radiance_g radiance_b: " + mesh.radiance_meaning + "\n";
  if (!mesh.radiance_stderr.empty()) {
    comments += "comment radiance_stderr: standard error of the luminance of the Monte Carlo estimate, same units\n";
  }
  bytes.insert(line_end + 1, comments);
}

void check_export(const std::filesystem::path& path, const ExportMesh& mesh) {
  const std::size_t n = mesh.points.size();
  if (!mesh.colours.empty() && mesh.colours.size() != n) {
    throw std::runtime_error(path.string() + ": " + std::to_string(mesh.colours.size()) + " colours for " +
                             std::to_string(n) + " vertices");
  }
  if (!mesh.radiance.empty() && mesh.radiance.size() != n) {
    throw std::runtime_error(path.string() + ": " + std::to_string(mesh.radiance.size()) +
                             " radiance values for " + std::to_string(n) + " vertices");
  }
  if (n > static_cast<std::size_t>(std::numeric_limits<int>::max())) {
    throw std::runtime_error(path.string() + ": too many vertices for PLY/OFF indices");
  }
  if (!mesh.radiance_stderr.empty() && mesh.radiance_stderr.size() != n) {
    throw std::runtime_error(path.string() + ": " + std::to_string(mesh.radiance_stderr.size()) +
                             " standard errors for " + std::to_string(n) + " vertices");
  }
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    for (int v : mesh.triangles[t]) {
      if (v < 0 || static_cast<std::size_t>(v) >= n) {
        throw std::runtime_error(path.string() + ": triangle " + std::to_string(t) + " has vertex index " +
                                 std::to_string(v) + ", not in [0, " + std::to_string(n) + ")");
      }
    }
  }
}

}  // namespace

bool is_mesh_output_format(const std::filesystem::path& path) {
  const std::string ext = lower_extension(path);
  return ext == ".ply" || ext == ".off";
}

void write_mesh(const std::filesystem::path& path, const ExportMesh& mesh) {
  AtomicOutputs outputs;
  write_mesh(outputs, path, mesh);
  outputs.publish();
}

void write_mesh(AtomicOutputs& outputs, const std::filesystem::path& path, const ExportMesh& mesh) {
  const std::string ext = lower_extension(path);
  OpenMesh::IO::Options options = OpenMesh::IO::Options::VertexColor;
  if (ext == ".ply") {
    options += OpenMesh::IO::Options::Binary;
    options += OpenMesh::IO::Options::Custom;
  } else if (ext == ".off") {
    // Geomview's OFF gives a COFF vertex colour four components (RGBA);
    // readers that follow it (assimp) reject three.
    options += OpenMesh::IO::Options::ColorAlpha;
  } else {
    throw std::runtime_error(path.string() + ": unknown mesh format '" + path.extension().string() +
                             "' (write .ply or .off)");
  }
  check_export(path, mesh);

  // Built completely before the target is touched, so a mesh OpenMesh cannot
  // take fails without side effects.
  TriMesh om;
  om.request_vertex_colors();
  OpenMesh::VPropHandleT<float> channel[3];
  for (int c = 0; c < 3; ++c) {
    om.add_property(channel[c], kRadianceNames[c]);
    om.property(channel[c]).set_persistent(true);
  }
  OpenMesh::VPropHandleT<float> stderr_channel;
  if (!mesh.radiance_stderr.empty()) {
    om.add_property(stderr_channel, kStderrName);
    om.property(stderr_channel).set_persistent(true);
  }
  om.reserve(mesh.points.size(), 3 * mesh.triangles.size(), mesh.triangles.size());
  for (std::size_t v = 0; v < mesh.points.size(); ++v) {
    const auto vh = om.add_vertex(mesh.points[v]);
    const auto c = mesh.colours.empty() ? kMissingColour : mesh.colours[v];
    om.set_color(vh, TriMesh::Color(c[0], c[1], c[2]));
    const Rgb r = mesh.radiance.empty() ? Rgb() : mesh.radiance[v];
    for (int ch = 0; ch < 3; ++ch) om.property(channel[ch], vh) = static_cast<float>(r[ch]);
    if (!mesh.radiance_stderr.empty()) om.property(stderr_channel, vh) = static_cast<float>(mesh.radiance_stderr[v]);
  }
  {
    const QuietOpenMesh quiet;
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
      const auto& tri = mesh.triangles[t];
      const auto fh = om.add_face(OpenMesh::VertexHandle(tri[0]), OpenMesh::VertexHandle(tri[1]),
                                  OpenMesh::VertexHandle(tri[2]));
      if (!fh.is_valid()) {
        throw std::runtime_error(path.string() + ": triangle " + std::to_string(t) + " (" + std::to_string(tri[0]) +
                                 "," + std::to_string(tri[1]) + "," + std::to_string(tri[2]) +
                                 ") is not manifold with the triangles before it, or repeats a vertex; "
                                 "each surface must be a manifold with its own vertices");
      }
    }
  }
  if (om.n_faces() != mesh.triangles.size()) {
    throw std::runtime_error(path.string() + ": only " + std::to_string(om.n_faces()) + " of " +
                             std::to_string(mesh.triangles.size()) + " triangles could be stored");
  }

  // Through a stream the library checks: OpenMesh's own file writer does not
  // see a failed write or close, and reported a truncated file as written.
  outputs.stage(path, [&](std::ostream& out) {
    const QuietOpenMesh quiet;
    if (ext != ".ply") {
      if (!OpenMesh::IO::write_mesh(om, out, ext, options, kTextPrecision)) {
        throw std::runtime_error(path.string() + ": cannot write mesh file");
      }
      return;
    }
    std::ostringstream buffer;
    if (!OpenMesh::IO::write_mesh(om, buffer, ext, options, kTextPrecision)) {
      throw std::runtime_error(path.string() + ": cannot write mesh file");
    }
    std::string bytes = std::move(buffer).str();
    add_ply_comments(bytes, path, mesh);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  });
}

RawMesh read_raw_mesh(const std::filesystem::path& path) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) throw InputError(path, "file not found");
  if (std::filesystem::is_directory(path, ec)) throw InputError(path, "is a directory, not a mesh file");
  const std::string ext = lower_extension(path);
  if (ext != ".ply" && ext != ".off") {
    throw InputError(path, "unknown mesh format '" + path.extension().string() + "' (expected .ply or .off)");
  }
  const std::uintmax_t size = std::filesystem::file_size(path, ec);
  if (ec) throw InputError(path, "cannot read: " + ec.message());
  if (size == 0) throw InputError(path, "file is empty");
  if (!std::ifstream(path, std::ios::binary)) throw InputError(path, "cannot open for reading");

  StoredMesh stored = read_ply_off(path, FaceIndices::kAsStored);
  RawMesh mesh;
  mesh.points = std::move(stored.points);
  mesh.faces = std::move(stored.faces);
  if (mesh.faces.empty()) throw InputError(path, "contains no faces");
  mesh.radiance = std::move(stored.radiance);
  mesh.radiance_stderr = std::move(stored.radiance_stderr);
  return mesh;
}

}  // namespace lhr
