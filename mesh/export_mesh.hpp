#pragma once
// The mesh lhr exports, in memory: the conforming triangles of all surfaces
// with per-vertex display colour and linear radiance (docs/design.md §3
// output). A plain value beside the meshes it is made from, so that render/
// builds it without depending on io/, whose io/mesh_io writes it as PLY or
// OFF (as mesh/image.hpp is to io/image_io).

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "mesh/types.hpp"

namespace lhr {

// The colour of a vertex that has none (ExportMesh::colours empty, or a
// surface appended without colours beside one with them): mid grey.
constexpr std::array<std::uint8_t, 3> kMissingColour{128, 128, 128};

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

}  // namespace lhr
