#include "io/mesh_io.hpp"
#include <stdexcept>
namespace lhr {
void append_to_export(ExportMesh&, const TriMesh&, const std::vector<Rgb>&) { throw std::logic_error("not implemented"); }
void write_mesh(const std::filesystem::path&, const ExportMesh&) { throw std::logic_error("not implemented"); }
RawMesh read_raw_mesh(const std::filesystem::path&) { throw std::logic_error("not implemented"); }
}  // namespace lhr
