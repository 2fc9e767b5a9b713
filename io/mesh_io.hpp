#pragma once
// Mesh files: written through OpenMesh's writers, read by lhr's own checking
// readers (io/ply_off_reader.hpp; docs/design.md §3 output). The ExportMesh
// they write is mesh/export_mesh.hpp, so that renderers build it without
// this file.

#include <filesystem>

#include "io/atomic_file.hpp"
#include "mesh/export_mesh.hpp"
#include "mesh/types.hpp"
#include "mesh/validate.hpp"

namespace lhr {

// By extension: .ply (binary, x y z, red green blue uchar, radiance_r/g/b
// float, radiance_stderr float when given) or .off (COFF, colours only). Written atomically. Throws std::runtime_error.
void write_mesh(const std::filesystem::path& path, const ExportMesh& mesh);
// The same, staged in a set of outputs published together.
void write_mesh(AtomicOutputs& outputs, const std::filesystem::path& path, const ExportMesh& mesh);
// Whether write_mesh knows path's format (.ply or .off, in any case), so a
// command can refuse its output name before the work.
bool is_mesh_output_format(const std::filesystem::path& path);

// The check_conforming_mesh tolerance for a mesh read from a file: PLY/OFF
// store float coordinates (relative rounding ~6e-8), so a T-vertex read back
// sits that far off its edge, and the in-memory default would miss it.
constexpr double kStoredMeshTolerance = 1e-6;

// Reads a PLY/OFF exactly as stored (no vertex merging, no face repair).
// Throws InputError.
RawMesh read_raw_mesh(const std::filesystem::path& path);

}  // namespace lhr
