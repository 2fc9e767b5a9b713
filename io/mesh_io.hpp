#pragma once
// Mesh files: written through OpenMesh's writers, read by lhr's own checking
// readers (io/ply_off_reader.hpp; docs/design.md §3 output).

#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "io/atomic_file.hpp"
#include "mesh/types.hpp"
#include "mesh/validate.hpp"

namespace lhr {

// What `lhr` exports: conforming triangles of all surfaces in one file, with
// per-vertex display colour and linear radiance.
struct ExportMesh {
  std::vector<Vec3> points;
  std::vector<std::array<int, 3>> triangles;
  std::vector<std::array<std::uint8_t, 3>> colours;  // per vertex, empty = grey
  std::vector<Rgb> radiance;                         // per vertex, empty = zero
  // Per vertex: standard error of the luminance of a Monte Carlo estimate
  // (lhr reference --at-vertices), PLY property radiance_stderr; empty = none.
  std::vector<double> radiance_stderr;
  // What red green blue and radiance_r/g/b hold, written as PLY header
  // comments (docs/design.md §3 output); a command writing something else says so.
  std::string colour_meaning = "display colour, tone-mapped and gamma-encoded (gamma 2.2), not linear";
  std::string radiance_meaning = "linear radiance, in the units of the scene's emission Ke";
};

// Appends a surface's conforming mesh; radiance per mesh vertex may be empty.
void append_to_export(ExportMesh& out, const TriMesh& mesh, const std::vector<Rgb>& radiance = {});

// By extension: .ply (binary, x y z, red green blue uchar, radiance_r/g/b
// float, radiance_stderr float when given) or .off (COFF, colours only). Written atomically. Throws std::runtime_error.
void write_mesh(const std::filesystem::path& path, const ExportMesh& mesh);
// The same, staged in a set of outputs published together.
void write_mesh(AtomicOutputs& outputs, const std::filesystem::path& path, const ExportMesh& mesh);

// The check_conforming_mesh tolerance for a mesh read from a file: PLY/OFF
// store float coordinates (relative rounding ~6e-8), so a T-vertex read back
// sits that far off its edge, and the in-memory default would miss it.
constexpr double kStoredMeshTolerance = 1e-6;

// Reads a PLY/OFF exactly as stored (no vertex merging, no face repair).
// Throws InputError.
RawMesh read_raw_mesh(const std::filesystem::path& path);

}  // namespace lhr
