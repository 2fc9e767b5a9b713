#pragma once
// PLY and OFF files through OpenMesh's readers, checked first (io/ internal).
// Those readers trust the file: header counts size allocations and loops, a
// header without a proper end_header line or with an unknown type makes the
// PLY reader loop, per-face vertex counts are taken as given, text that does
// not parse turns into silent zeros, and the binary readers run on past the
// end of the data. Everything they would trust is checked here before they
// see it, so every bad file is one InputError naming the file and the line
// or element (docs/design.md §3; docs/robustness.md lists what the fuzzers found).

#include <filesystem>

#include "io/openmesh_import.hpp"

namespace lhr {

enum class FaceIndices {
  kInRange,   // loading a scene: >= 3 distinct vertices per face, all in range
  kAsStored,  // `lhr validate`: any int, judged afterwards by the conforming check
};

// Reads a .ply or .off file into importer, which then holds exactly the
// vertices and faces the header declares, their colours and any further
// PLY vertex properties (in importer.properties()). Throws InputError.
void read_ply_off(const std::filesystem::path& path, PlainImporter& importer, FaceIndices faces);

}  // namespace lhr
