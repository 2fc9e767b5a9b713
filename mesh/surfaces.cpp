#include "mesh/surfaces.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "mesh/rgb.hpp"
#include "mesh/union_find.hpp"

namespace lhr {

namespace {

// Faces whose area is at most this fraction of their longest edge squared
// (a height under 2e-12 of their length) have no usable normal
// (docs/design.md §3). Judged per face: a 1 cm box in a 10 km scene is
// small, not degenerate.
constexpr double kZeroAreaRelative = 1e-12;
// A surface is planar when every point lies within this fraction of its
// extent from the best-fit plane; planar surfaces get the 2D mesher (docs/design.md §4).
constexpr double kPlanarRelative = 1e-6;

// Twice the vector area of a polygon (Newell's method). Summing cross
// products about the first point keeps it accurate far from the origin.
Vec3 newell_vector(const std::vector<Vec3>& points, const std::vector<int>& polygon) {
  Vec3 sum(0, 0, 0);
  const Vec3& origin = points[polygon[0]];
  for (std::size_t i = 1; i + 1 < polygon.size(); ++i) {
    sum += OpenMesh::cross(points[polygon[i]] - origin, points[polygon[i + 1]] - origin);
  }
  return sum;
}

// Positions that are bit-for-bit equal (with -0 == +0) share an id: OBJ
// exporters duplicate vertices per face, which must not cut a surface.
template <typename EverySoOften>
std::vector<int> weld_positions(const std::vector<Vec3>& points, const EverySoOften& every_so_often) {
  std::map<std::array<double, 3>, int> ids;
  std::vector<int> weld(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    every_so_often(i);
    const std::array<double, 3> key{points[i][0] + 0.0, points[i][1] + 0.0, points[i][2] + 0.0};
    weld[i] = ids.emplace(key, static_cast<int>(ids.size())).first->second;
  }
  return weld;
}

// The angle between two unit vectors, accurate near 0 and 180 degrees.
double angle_deg(const Vec3& a, const Vec3& b) {
  return std::atan2(OpenMesh::cross(a, b).norm(), OpenMesh::dot(a, b)) * 180.0 / M_PI;
}

}  // namespace

namespace {

// Relative to the scene's size: how far an emitter lying on a coplanar
// surface is moved in front of it. Well above the ray offsets of the
// visibility and path-tracing code (1e-5 of the scene), well below anything
// a picture or a form factor could show.
constexpr double kCoplanarLift = 1e-4;
constexpr double kUnbounded = std::numeric_limits<double>::infinity();

// Whether two planar surfaces with the same front overlap in their common
// plane: their bounding rectangles in that plane share an area.
bool overlap_in_plane(const Surface& a, const Surface& b, double tolerance) {
  const Vec3& n = a.normal;
  const Vec3 u = (std::abs(n[0]) < 0.9 ? OpenMesh::cross(n, Vec3(1, 0, 0)) : OpenMesh::cross(n, Vec3(0, 1, 0))).normalized();
  const Vec3 v = OpenMesh::cross(n, u);
  const auto rectangle = [&](const Surface& s) {
    std::array<double, 4> r{kUnbounded, -kUnbounded, kUnbounded, -kUnbounded};
    for (const Vec3& p : s.points) {
      r[0] = std::min(r[0], OpenMesh::dot(p, u));
      r[1] = std::max(r[1], OpenMesh::dot(p, u));
      r[2] = std::min(r[2], OpenMesh::dot(p, v));
      r[3] = std::max(r[3], OpenMesh::dot(p, v));
    }
    return r;
  };
  const auto ra = rectangle(a), rb = rectangle(b);
  return std::min(ra[1], rb[1]) - std::max(ra[0], rb[0]) > tolerance &&
         std::min(ra[3], rb[3]) - std::max(ra[2], rb[2]) > tolerance;
}

void lift_coplanar_emitters(const PolygonSoup& soup, SurfaceSplit& split) {
  Vec3 lo(kUnbounded, kUnbounded, kUnbounded), hi(-kUnbounded, -kUnbounded, -kUnbounded);
  double magnitude = 0.0;
  for (const Surface& s : split.surfaces) {
    for (const Vec3& p : s.points) {
      lo.minimize(p);
      hi.maximize(p);
      magnitude = std::max({magnitude, std::abs(p[0]), std::abs(p[1]), std::abs(p[2])});
    }
  }
  const double diagonal = split.surfaces.empty() ? 0.0 : (hi - lo).norm();
  const double lift = kCoplanarLift * std::max(diagonal, magnitude);
  const double on_plane = kPlanarRelative * std::max(diagonal, magnitude);
  for (std::size_t e = 0; e < split.surfaces.size(); ++e) {
    Surface& emitter = split.surfaces[e];
    if (!emitter.planar || !soup.materials[emitter.material].is_emitter()) continue;
    for (std::size_t o = 0; o < split.surfaces.size(); ++o) {
      const Surface& other = split.surfaces[o];
      if (o == e || !other.planar || OpenMesh::dot(other.normal, emitter.normal) < 1.0 - 1e-9) continue;
      if (std::abs(OpenMesh::dot(other.normal, emitter.points.front() - other.points.front())) > on_plane) continue;
      if (!overlap_in_plane(emitter, other, on_plane)) continue;
      for (Vec3& p : emitter.points) p += lift * emitter.normal;
      split.lifted_emitters.emplace_back(static_cast<int>(e), static_cast<int>(o));
      split.lift_distance = lift;
      break;
    }
  }
}

// Pieces of a light that reflects nothing, lying in one plane with one
// material inside one group, shoot as one surface whether they touch or not
// (docs/design.md §3, "Panels of lights"): a ceiling of ten thousand small
// lamps is then one shooter whose cluster tree opens only where a receiver
// needs it, not ten thousand shooters each linked to every receiver's
// initial vertices. Such a piece has a fixed radiance and receives nothing,
// so joining it to another changes no value, only how the light is shot.
// Pieces whose union would not pass the planarity test stay apart.
void unite_light_panels(const PolygonSoup& soup, const std::vector<std::vector<int>>& welded,
                        const std::vector<Vec3>& normal, const std::vector<double>& area,
                        const std::vector<bool>& kept, UnionFind& components) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  const auto panel_material = [&](int m) {
    // Black as the solvers judge a receiver that reflects nothing.
    const Material& material = soup.materials.at(m);
    return material.is_emitter() && !(max_channel(material.reflectance) > 0);
  };
  struct Piece {
    std::vector<int> faces;
    Vec3 newell{0, 0, 0};
    Vec3 lo{kInf, kInf, kInf}, hi{-kInf, -kInf, -kInf};
  };
  std::map<int, Piece> pieces;  // by component root
  Vec3 scene_lo(kInf, kInf, kInf), scene_hi(-kInf, -kInf, -kInf);
  for (std::size_t f = 0; f < soup.faces.size(); ++f) {
    if (!kept[f]) continue;
    for (int v : welded[f]) {
      scene_lo.minimize(soup.points[v]);
      scene_hi.maximize(soup.points[v]);
    }
    if (!panel_material(soup.faces[f].material)) continue;
    Piece& piece = pieces[components.find(static_cast<int>(f))];
    piece.faces.push_back(static_cast<int>(f));
    piece.newell += 2.0 * area[f] * normal[f];
    for (int v : welded[f]) {
      piece.lo.minimize(soup.points[v]);
      piece.hi.maximize(soup.points[v]);
    }
  }
  const double diagonal = (scene_hi - scene_lo).norm();
  if (pieces.size() < 2 || !(diagonal > 0.0)) return;

  // Points within half the planarity tolerance of the plane through their
  // centroid with the summed normal, so that the surface made of them is
  // planar by the test below with room to spare.
  const auto planar_together = [&](const std::vector<const Piece*>& set) {
    Vec3 sum(0, 0, 0), centroid(0, 0, 0), lo(kInf, kInf, kInf), hi(-kInf, -kInf, -kInf);
    std::size_t count = 0;
    for (const Piece* piece : set) {
      sum += piece->newell;
      lo.minimize(piece->lo);
      hi.maximize(piece->hi);
      for (int f : piece->faces) {
        for (int v : welded[f]) centroid += soup.points[v];
        count += welded[f].size();
      }
    }
    const double sum_norm = sum.norm();
    if (!(sum_norm > 0.0)) return false;
    const Vec3 n = sum / sum_norm;
    centroid /= static_cast<double>(count);
    const double tolerance = 0.5 * kPlanarRelative * (hi - lo).norm();
    for (const Piece* piece : set) {
      for (int f : piece->faces) {
        for (int v : welded[f]) {
          if (std::abs(OpenMesh::dot(soup.points[v] - centroid, n)) > tolerance) return false;
        }
      }
    }
    return true;
  };

  // Candidates share group, material, normal (to 10⁻⁶) and offset (to 10⁻⁷ of
  // the scene): a plane cut by a bin's edge only leaves two panels apart.
  std::map<std::array<long long, 6>, std::vector<int>> candidates;
  for (const auto& [root, piece] : pieces) {
    if (!planar_together({&piece})) continue;  // a curved piece stays a surface of its own
    const Vec3 n = piece.newell / piece.newell.norm();
    const InputFace& face = soup.faces[piece.faces.front()];
    const double offset = OpenMesh::dot(n, soup.points[welded[piece.faces.front()].front()]);
    candidates[{face.group, face.material, std::llround(n[0] * 1e6), std::llround(n[1] * 1e6),
                std::llround(n[2] * 1e6), std::llround(offset / (1e-7 * diagonal))}]
        .push_back(root);
  }
  for (const auto& [key, roots] : candidates) {
    if (roots.size() < 2) continue;
    std::vector<const Piece*> set;
    for (int root : roots) set.push_back(&pieces.at(root));
    if (!planar_together(set)) continue;
    for (int root : roots) components.unite(roots.front(), root);
  }
}

}  // namespace

SurfaceSplit split_into_surfaces(const PolygonSoup& soup, double crease_angle_deg,
                                 const std::function<void()>& checkpoint) {
  if (!std::isfinite(crease_angle_deg) || crease_angle_deg < 0.0 || crease_angle_deg > 180.0) {
    throw std::invalid_argument("crease angle must be in [0, 180] degrees, got " +
                                std::to_string(crease_angle_deg));
  }
  SurfaceSplit split;
  const std::size_t n_faces = soup.faces.size();
  constexpr std::size_t kItemsPerCheckpoint = 4096;
  const auto every_so_often = [&](std::size_t i) {
    if (checkpoint && i % kItemsPerCheckpoint == 0) checkpoint();
  };

  constexpr double kInf = std::numeric_limits<double>::infinity();
  const std::vector<int> weld = weld_positions(soup.points, every_so_often);

  // Welded polygons, with vertices that collapsed onto their neighbour removed.
  std::vector<std::vector<int>> welded(n_faces);
  std::vector<Vec3> normal(n_faces, Vec3(0, 0, 0));
  std::vector<double> area(n_faces, 0.0);
  std::vector<bool> kept(n_faces, false);
  for (std::size_t f = 0; f < n_faces; ++f) {
    every_so_often(f);
    const std::vector<int>& in = soup.faces[f].vertices;
    std::vector<int>& out = welded[f];
    for (int v : in) {
      if (out.empty() || weld[v] != weld[out.back()]) out.push_back(v);
    }
    while (out.size() > 1 && weld[out.front()] == weld[out.back()]) out.pop_back();
    if (out.size() < 3) continue;
    const Vec3 n = newell_vector(soup.points, out);
    area[f] = 0.5 * n.norm();
    double longest = 0.0;
    for (std::size_t k = 0; k < out.size(); ++k) {
      longest = std::max(longest, (soup.points[out[k]] - soup.points[out[(k + 1) % out.size()]]).sqrnorm());
    }
    if (!(area[f] > kZeroAreaRelative * longest)) continue;
    normal[f] = n / n.norm();
    kept[f] = true;
  }
  split.dropped_zero_area_faces = static_cast<int>(std::count(kept.begin(), kept.end(), false));

  // Faces meeting along an undirected welded edge.
  std::map<std::pair<int, int>, std::vector<int>> edge_faces;
  for (std::size_t f = 0; f < n_faces; ++f) {
    every_so_often(f);
    if (!kept[f]) continue;
    const std::vector<int>& poly = welded[f];
    for (std::size_t i = 0; i < poly.size(); ++i) {
      int a = weld[poly[i]];
      int b = weld[poly[(i + 1) % poly.size()]];
      if (a > b) std::swap(a, b);
      edge_faces[{a, b}].push_back(static_cast<int>(f));
    }
  }
  UnionFind components(n_faces);
  std::size_t edges_seen = 0;
  for (const auto& [edge, faces] : edge_faces) {
    every_so_often(edges_seen++);
    // An edge of more than two faces (a fin, a T-junction of walls) joins
    // none of them: each side becomes a surface of its own, which a quadtree
    // can carry, and the loader reports how many such edges it cut.
    if (faces.size() > 2) {
      ++split.non_manifold_edges;
      continue;
    }
    for (std::size_t i = 0; i < faces.size(); ++i) {
      for (std::size_t j = i + 1; j < faces.size(); ++j) {
        const InputFace& a = soup.faces[faces[i]];
        const InputFace& b = soup.faces[faces[j]];
        if (a.material != b.material || a.group != b.group) continue;
        if (angle_deg(normal[faces[i]], normal[faces[j]]) > crease_angle_deg) continue;
        components.unite(faces[i], faces[j]);
      }
    }
  }

  unite_light_panels(soup, welded, normal, area, kept, components);

  // Roots are each component's first face, so visiting faces in order gives
  // surfaces ordered by first face index.
  std::map<int, std::size_t> surface_of_root;
  std::vector<std::map<int, int>> local_index;  // welded id -> index in the surface
  std::vector<Vec3> newell_sum;
  std::map<std::pair<int, int>, int> count_per_name;
  for (std::size_t f = 0; f < n_faces; ++f) {
    every_so_often(f);
    if (!kept[f]) continue;
    const int root = components.find(static_cast<int>(f));
    auto [it, inserted] = surface_of_root.emplace(root, split.surfaces.size());
    if (inserted) {
      const InputFace& face = soup.faces[f];
      Surface s;
      s.material = face.material;
      const int k = count_per_name[{face.group, face.material}]++;
      s.name =
          soup.groups.at(face.group) + "/" + soup.materials.at(face.material).name + "#" + std::to_string(k);
      split.surfaces.push_back(std::move(s));
      local_index.emplace_back();
      newell_sum.emplace_back(0, 0, 0);
    }
    const std::size_t si = it->second;
    Surface& s = split.surfaces[si];
    std::vector<int> polygon;
    polygon.reserve(welded[f].size());
    for (int v : welded[f]) {
      auto [li, fresh] = local_index[si].emplace(weld[v], static_cast<int>(s.points.size()));
      if (fresh) s.points.push_back(soup.points[v]);
      polygon.push_back(li->second);
    }
    s.polygons.push_back(std::move(polygon));
    s.area += area[f];
    newell_sum[si] += 2.0 * area[f] * normal[f];
  }

  // Seams: edges whose faces lie in more than one surface, recorded in each.
  std::vector<std::size_t> surface_of_face(n_faces, 0);
  for (std::size_t f = 0; f < n_faces; ++f) {
    if (kept[f]) surface_of_face[f] = surface_of_root.at(components.find(static_cast<int>(f)));
  }
  edges_seen = 0;
  for (const auto& [edge, faces] : edge_faces) {
    every_so_often(edges_seen++);
    // A structured binding cannot be captured by a lambda before C++20's P1091 (clang 14).
    const std::size_t first_surface = surface_of_face[faces[0]];
    const bool seam = std::any_of(faces.begin(), faces.end(),
                                  [&](int f) { return surface_of_face[f] != first_surface; });
    if (!seam) continue;
    std::vector<std::size_t> recorded;
    for (int f : faces) {
      const std::size_t si = surface_of_face[f];
      if (std::find(recorded.begin(), recorded.end(), si) != recorded.end()) continue;
      recorded.push_back(si);
      split.surfaces[si].seam_edges.emplace_back(local_index[si].at(edge.first), local_index[si].at(edge.second));
    }
  }

  for (std::size_t si = 0; si < split.surfaces.size(); ++si) {
    Surface& s = split.surfaces[si];
    Vec3 slo(kInf, kInf, kInf);
    Vec3 shi(-kInf, -kInf, -kInf);
    Vec3 centroid(0, 0, 0);
    for (const Vec3& p : s.points) {
      slo.minimize(p);
      shi.maximize(p);
      centroid += p;
    }
    centroid /= static_cast<double>(s.points.size());
    const double extent = (shi - slo).norm();
    // A closed or strongly curved surface has a near-zero summed normal; it
    // is not planar and its largest polygon gives a representative front.
    const double sum_norm = newell_sum[si].norm();
    if (sum_norm > 1e-9 * 2.0 * s.area) {
      s.normal = newell_sum[si] / sum_norm;
      s.planar = std::all_of(s.points.begin(), s.points.end(), [&](const Vec3& p) {
        return std::abs(OpenMesh::dot(p - centroid, s.normal)) <= kPlanarRelative * extent;
      });
    } else {
      double best = -1.0;
      for (const std::vector<int>& poly : s.polygons) {
        const Vec3 n = newell_vector(s.points, poly);
        if (n.norm() > best) {
          best = n.norm();
          s.normal = n / n.norm();
        }
      }
      s.planar = false;
    }
  }
  lift_coplanar_emitters(soup, split);
  return split;
}

}  // namespace lhr
