#include "radiosity/element_floor.hpp"

#include <algorithm>
#include <cmath>

namespace lhr {

namespace {

// Edge of the smallest elements next to a small surface, as a fraction of its
// size: a spot of the surface's size is then covered by about 8 × 8 element
// edges, which brings the reflected power of the small-light cases of
// tests/test_small_lights.cpp within 3 % with both bases.
constexpr double kPartnerFraction = 1.0 / 8.0;

// Elements across a thin surface's width, as for a small partner.
constexpr double kWidthFraction = 1.0 / 8.0;

double area_of_edge(double edge) { return std::sqrt(3.0) / 4.0 * edge * edge; }

double size_of(const Surface& surface) {
  if (surface.points.empty()) return 0.0;
  Vec3 lo = surface.points.front(), hi = lo;
  for (const Vec3& p : surface.points) {
    lo.minimize(p);
    hi.maximize(p);
  }
  return (hi - lo).norm();
}

// A surface's width, 2A/P: w for a long strip of width w, half the side of
// a square. A closed surface has no border, and no width to bound.
double width_of(const MeshedScene& model, int s) {
  const TriMesh& mesh = model.hierarchy(s).mesh();
  double border = 0.0;
  for (const auto heh : mesh.halfedges()) {
    if (mesh.is_boundary(heh)) border += mesh.calc_edge_length(heh);
  }
  return border > 0.0 ? 2.0 * model.surface_area(s) / border : 0.0;
}

}  // namespace

ElementFloor::ElementFloor(const MeshedScene& model, double min_edge) {
  const double scene_floor = min_edge > 0 ? min_edge : model.max_edge() / 32.0;
  scene_min_area_ = area_of_edge(scene_floor);
  for (int s = 0; s < model.num_surfaces(); ++s) {
    double edge = scene_floor;
    if (!(min_edge > 0)) {
      const double partner = kPartnerFraction * size_of(model.scene().surfaces[s]);
      if (partner > 0) edge = std::min(edge, partner);
    }
    min_area_.push_back(area_of_edge(edge));
    double own = scene_floor;
    if (!(min_edge > 0)) {
      const double width = kWidthFraction * width_of(model, s);
      if (width > 0) own = std::min(own, width);
    }
    own_min_area_.push_back(area_of_edge(own));
  }
}

}  // namespace lhr
