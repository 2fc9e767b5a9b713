#pragma once
// The input polygons of a planar surface split into triangles, in the
// surface's (u, v) frame: the piecewise-linear shape that Steiner points are
// placed on, and the region the mesh must cover (mesh/planar_mesh.hpp). A
// uniform grid over them finds the triangle a point lies in.

#include <array>
#include <cstddef>
#include <limits>
#include <vector>

#include "mesh/point2.hpp"

namespace lhr {

class PointLocator {
 public:
  PointLocator(std::vector<Point2> points2, std::vector<std::array<int, 3>> triangles);

  const std::vector<std::array<int, 3>>& triangles() const { return triangles_; }

  struct Location {
    int triangle = -1;
    std::array<double, 3> barycentric{0, 0, 0};
    double min_barycentric = -std::numeric_limits<double>::infinity();
  };

  // The input triangle that contains p best (largest smallest barycentric
  // coordinate); min_barycentric < 0 means p lies outside all of them.
  Location locate(const Point2& p) const;

 private:
  void build_grid();
  int clamp_x(double x) const;
  int clamp_y(double y) const;
  std::size_t cell_of(const Point2& p) const;

  std::vector<Point2> points2_;
  std::vector<std::array<int, 3>> triangles_;
  int nx_ = 1, ny_ = 1;
  double x0_ = 0, y0_ = 0, sx_ = 1, sy_ = 1;
  std::vector<std::vector<int>> cells_;
};

}  // namespace lhr
