#include "mesh/point_locator.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

namespace lhr {

PointLocator::PointLocator(std::vector<Point2> points2, std::vector<std::array<int, 3>> triangles)
    : points2_(std::move(points2)), triangles_(std::move(triangles)) {
  build_grid();
}

PointLocator::Location PointLocator::locate(const Point2& p) const {
  Location best;
  const auto& cell = cells_[cell_of(p)];
  for (int t : cell) {
    const auto& tri = triangles_[t];
    const Point2& a = points2_[tri[0]];
    const Point2& b = points2_[tri[1]];
    const Point2& c = points2_[tri[2]];
    const double area = orient2(a, b, c);
    const std::array<double, 3> w{orient2(p, b, c) / area, orient2(a, p, c) / area, orient2(a, b, p) / area};
    const double m = std::min({w[0], w[1], w[2]});
    if (m > best.min_barycentric) best = Location{t, w, m};
  }
  return best;
}

void PointLocator::build_grid() {
  double x0 = std::numeric_limits<double>::infinity(), y0 = x0;
  double x1 = -x0, y1 = -x0;
  for (const auto& tri : triangles_) {
    for (int i : tri) {
      x0 = std::min(x0, points2_[i].x);
      y0 = std::min(y0, points2_[i].y);
      x1 = std::max(x1, points2_[i].x);
      y1 = std::max(y1, points2_[i].y);
    }
  }
  const double w = std::max(x1 - x0, 1e-300);
  const double h = std::max(y1 - y0, 1e-300);
  const double n = static_cast<double>(triangles_.size());
  nx_ = static_cast<int>(std::clamp(std::ceil(std::sqrt(n * w / h)), 1.0, 512.0));
  ny_ = static_cast<int>(std::clamp(std::ceil(std::sqrt(n * h / w)), 1.0, 512.0));
  x0_ = x0;
  y0_ = y0;
  sx_ = nx_ / w;
  sy_ = ny_ / h;
  cells_.assign(static_cast<std::size_t>(nx_) * ny_, {});
  // Slack so points rounded onto a triangle's edge still find it.
  const double pad = 1e-9 * std::hypot(w, h);
  for (std::size_t t = 0; t < triangles_.size(); ++t) {
    double tx0 = std::numeric_limits<double>::infinity(), ty0 = tx0, tx1 = -tx0, ty1 = -tx0;
    for (int i : triangles_[t]) {
      tx0 = std::min(tx0, points2_[i].x);
      ty0 = std::min(ty0, points2_[i].y);
      tx1 = std::max(tx1, points2_[i].x);
      ty1 = std::max(ty1, points2_[i].y);
    }
    const int i0 = clamp_x(tx0 - pad), i1 = clamp_x(tx1 + pad);
    const int j0 = clamp_y(ty0 - pad), j1 = clamp_y(ty1 + pad);
    for (int j = j0; j <= j1; ++j) {
      for (int i = i0; i <= i1; ++i) cells_[static_cast<std::size_t>(j) * nx_ + i].push_back(static_cast<int>(t));
    }
  }
}

int PointLocator::clamp_x(double x) const {
  return std::clamp(static_cast<int>(std::floor((x - x0_) * sx_)), 0, nx_ - 1);
}

int PointLocator::clamp_y(double y) const {
  return std::clamp(static_cast<int>(std::floor((y - y0_) * sy_)), 0, ny_ - 1);
}

std::size_t PointLocator::cell_of(const Point2& p) const {
  return static_cast<std::size_t>(clamp_y(p.y)) * nx_ + clamp_x(p.x);
}

}  // namespace lhr
