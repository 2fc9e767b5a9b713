#pragma once
// A point in a planar surface's own (u, v) frame, where its initial mesh is
// made (mesh/planar_mesh.hpp). Plain doubles, so that only the translation
// unit that calls CGAL (mesh/cgal_meshing.cpp) needs CGAL's types.

#include <cmath>

namespace lhr {

struct Point2 {
  double x = 0.0;
  double y = 0.0;
  friend bool operator==(const Point2&, const Point2&) = default;
};

// Twice the signed area of (a, b, c): positive when counter-clockwise. Not
// exact: where the sign must be right, mesh/cgal_meshing.cpp asks CGAL.
inline double orient2(const Point2& a, const Point2& b, const Point2& c) {
  return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
}

inline double squared_distance(const Point2& a, const Point2& b) {
  const double dx = a.x - b.x, dy = a.y - b.y;
  return dx * dx + dy * dy;
}

inline double distance(const Point2& a, const Point2& b) { return std::sqrt(squared_distance(a, b)); }

// a + t (b − a).
inline Point2 lerp(const Point2& a, const Point2& b, double t) {
  return Point2{a.x + t * (b.x - a.x), a.y + t * (b.y - a.y)};
}

}  // namespace lhr
