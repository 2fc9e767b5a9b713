#include "mesh/triangle_geometry.hpp"

namespace lhr {

Vec3 closest_point(const Vec3& p, const std::array<Vec3, 3>& t) {
  // The Voronoi regions of the corners, then of the edges, then the face
  // (Ericson, Real-Time Collision Detection, §5.1.5).
  const Vec3 &a = t[0], &b = t[1], &c = t[2];
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = OpenMesh::dot(ab, ap), d2 = OpenMesh::dot(ac, ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const Vec3 bp = p - b;
  const double d3 = OpenMesh::dot(ab, bp), d4 = OpenMesh::dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + (d1 / (d1 - d3)) * ab;
  const Vec3 cp = p - c;
  const double d5 = OpenMesh::dot(ab, cp), d6 = OpenMesh::dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + (d2 / (d2 - d6)) * ac;
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0) return b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b);
  const double sum = va + vb + vc;
  if (!(sum > 0)) return a;  // degenerate triangle
  return a + (vb / sum) * ab + (vc / sum) * ac;
}

}  // namespace lhr
