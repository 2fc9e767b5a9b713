#include "mesh/initial_mesh.hpp"

#include <cmath>
#include <exception>
#include <stdexcept>
#include <string>

#include "mesh/curved_mesh.hpp"
#include "mesh/meshing_checkpoint.hpp"
#include "mesh/planar_mesh.hpp"

namespace lhr {

namespace {

void check_options(const MeshingOptions& options) {
  if (!(options.max_edge > 0.0) || !std::isfinite(options.max_edge)) {
    throw std::invalid_argument("meshing: max edge length must be a positive finite number, got " +
                                std::to_string(options.max_edge));
  }
  if (!(options.min_angle_deg > 0.0) || !(options.min_angle_deg < 60.0)) {
    throw std::invalid_argument("meshing: minimum angle must be in (0, 60) degrees, got " +
                                std::to_string(options.min_angle_deg));
  }
}

void check_polygons(const Surface& surface) {
  if (surface.polygons.empty()) throw std::runtime_error("has no polygons");
  const int n = static_cast<int>(surface.points.size());
  for (std::size_t p = 0; p < surface.polygons.size(); ++p) {
    const auto& poly = surface.polygons[p];
    if (poly.size() < 3) {
      throw std::runtime_error("polygon " + std::to_string(p) + " has fewer than 3 vertices");
    }
    for (int i : poly) {
      if (i < 0 || i >= n) {
        throw std::runtime_error("polygon " + std::to_string(p) + " refers to point " + std::to_string(i) +
                                 " of " + std::to_string(n));
      }
      for (int k = 0; k < 3; ++k) {
        if (!std::isfinite(surface.points[i][k])) {
          throw std::runtime_error("point " + std::to_string(i) + " is not finite");
        }
      }
    }
  }
}

}  // namespace

double default_max_edge(const Scene& scene) {
  const double diagonal = scene_bounds(scene).diagonal();
  if (!(diagonal > 0.0) || !std::isfinite(diagonal)) {
    throw std::runtime_error("scene '" + scene.source +
                             "' has no extent, so no default maximum edge length; give --max-edge");
  }
  // docs/design.md §4: the minimum density h defaults to a fraction of the scene size.
  return diagonal / 20.0;
}

TriMesh mesh_surface(const Surface& surface, const MeshingOptions& options, const std::vector<Segment3>& contacts,
                     double contact_tolerance) {
  check_options(options);
  try {
    check_polygons(surface);
    if (!surface.planar) return mesh_curved(surface, options);
    if (!contacts.empty()) {
      // Contact lines sharpen the mesh but are not needed for a valid one:
      // should they defeat the mesher (near-degenerate crossings), the
      // surface is meshed as if nothing touched it.
      try {
        return mesh_planar(surface, options, contacts, contact_tolerance);
      } catch (const std::exception&) {
      }
    }
    return mesh_planar(surface, options, {}, 0.0);
  } catch (const CheckpointThrew& stop) {
    std::rethrow_exception(stop.thrown);
  } catch (const std::exception& e) {
    throw std::runtime_error("surface '" + surface.name + "': " + e.what());
  }
}

}  // namespace lhr
