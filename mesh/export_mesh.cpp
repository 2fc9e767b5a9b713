#include "mesh/export_mesh.hpp"

#include <stdexcept>
#include <string>

namespace lhr {

void append_to_export(ExportMesh& out, const TriMesh& mesh, const std::vector<Rgb>& radiance) {
  if (!radiance.empty() && radiance.size() != mesh.n_vertices()) {
    throw std::invalid_argument("append_to_export: " + std::to_string(radiance.size()) + " radiance values for a mesh of " +
                                std::to_string(mesh.n_vertices()) + " vertices");
  }
  const std::size_t offset = out.points.size();
  // Keep per-vertex arrays aligned with points even if earlier surfaces had
  // no colours: missing colours are grey, missing radiance is zero.
  out.radiance.resize(offset, Rgb());
  const bool colours = mesh.has_vertex_colors() || !out.colours.empty();
  if (colours) out.colours.resize(offset, kMissingColour);

  std::vector<int> index(mesh.n_vertices(), -1);
  for (const auto vh : mesh.vertices()) {  // skips deleted vertices
    index[vh.idx()] = static_cast<int>(out.points.size());
    out.points.push_back(mesh.point(vh));
    out.radiance.push_back(radiance.empty() ? Rgb() : radiance[vh.idx()]);
    if (colours) {
      if (mesh.has_vertex_colors()) {
        const auto c = mesh.color(vh);
        out.colours.push_back({c[0], c[1], c[2]});
      } else {
        out.colours.push_back(kMissingColour);
      }
    }
  }
  for (const auto fh : mesh.faces()) {
    std::array<int, 3> tri{};
    int k = 0;
    for (const auto vh : mesh.fv_range(fh)) {
      if (k < 3) tri[k] = index[vh.idx()];
      ++k;
    }
    if (k != 3) throw std::invalid_argument("append_to_export: face " + std::to_string(fh.idx()) + " is not a triangle");
    out.triangles.push_back(tri);
  }
}

}  // namespace lhr
