#include "mesh/validate.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <iterator>
#include <limits>
#include <numeric>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "mesh/edge_key.hpp"
#include "mesh/union_find.hpp"

namespace lhr {

namespace {

// Enough examples to locate a problem; a broken mesh of a million faces would
// otherwise bury the report.
constexpr std::size_t kMaxReportsPerKind = 20;

class Report {
 public:
  void add(const std::string& kind, std::string where, std::string detail) {
    Entry& e = entry(kind);
    ++e.total;
    if (e.listed.size() < kMaxReportsPerKind) {
      e.listed.push_back(Violation{kind, std::move(where), std::move(detail)});
    }
  }

  std::vector<Violation> take() {
    std::vector<Violation> out;
    for (Entry& e : entries_) {
      for (Violation& v : e.listed) out.push_back(std::move(v));
      if (e.total > e.listed.size()) {
        out.push_back(Violation{e.kind, "mesh",
                                std::to_string(e.total - e.listed.size()) + " more not listed (" +
                                    std::to_string(e.total) + " in total)"});
      }
    }
    return out;
  }

 private:
  struct Entry {
    std::string kind;
    std::size_t total = 0;
    std::vector<Violation> listed;
  };

  Entry& entry(const std::string& kind) {
    for (Entry& e : entries_) {
      if (e.kind == kind) return e;
    }
    entries_.push_back(Entry{kind, 0, {}});
    return entries_.back();
  }

  std::vector<Entry> entries_;  // in order of first occurrence, so reports group by kind
};

// Positions (Vec3) and radiances (Rgb) alike.
template <typename Triple>
bool finite(const Triple& p) { return std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]); }

std::string vertex_at(int v) { return "vertex " + std::to_string(v); }
std::string face_at(std::size_t f) { return "face " + std::to_string(f); }
std::string edge_at(int a, int b) { return "edge (" + std::to_string(a) + "," + std::to_string(b) + ")"; }

template <typename Triple>
std::string format_point(const Triple& p) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "(%.9g, %.9g, %.9g)", p[0], p[1], p[2]);
  return buf;
}

// One side of an undirected edge as one face uses it.
struct EdgeUse {
  std::uint64_t key;
  int face;
  int corner_lo;  // corner (face-vertex slot) of the smaller vertex index
  int corner_hi;
  bool forward;   // the face walks the edge from the smaller to the larger index
};

// Uniform grid over vertex positions, hashed, so a T-junction query touches
// only the cells a boundary edge passes through (~O(n) overall).
class VertexGrid {
 public:
  VertexGrid(const std::vector<Vec3>& points, const std::vector<int>& vertices, const Vec3& origin,
             double cell)
      : origin_(origin), cell_(cell) {
    std::vector<std::pair<std::uint64_t, int>> keyed;
    keyed.reserve(vertices.size());
    for (int v : vertices) keyed.emplace_back(key_of(cell_index(points[v])), v);
    std::sort(keyed.begin(), keyed.end());
    sorted_.reserve(keyed.size());
    for (std::size_t i = 0; i < keyed.size(); ++i) {
      if (i == 0 || keyed[i].first != keyed[i - 1].first) {
        ranges_.emplace(keyed[i].first, std::make_pair(static_cast<int>(i), static_cast<int>(i)));
      }
      ranges_[keyed[i].first].second = static_cast<int>(i) + 1;
      sorted_.push_back(keyed[i].second);
    }
  }

  // Calls visit(v) once for every vertex within `reach` of segment ab (and
  // some more nearby; callers test exactly).
  template <typename Visit>
  void near_segment(const Vec3& a, const Vec3& b, double reach, std::vector<std::uint64_t>& cells,
                    Visit&& visit) const {
    // Pieces at most half a cell long, each dilated by reach: a point within
    // reach of the segment lies in the box of the piece holding its closest
    // point, and each box overlaps only a few cells.
    const double length = (b - a).norm();
    const int pieces = std::max(1, static_cast<int>(std::ceil(2.0 * length / cell_)));
    cells.clear();
    for (int s = 0; s < pieces; ++s) {
      const Vec3 p = a + (b - a) * (static_cast<double>(s) / pieces);
      const Vec3 q = a + (b - a) * (static_cast<double>(s + 1) / pieces);
      Vec3 lo = p;
      Vec3 hi = p;
      lo.minimize(q);
      hi.maximize(q);
      const std::array<long, 3> c0 = cell_index(lo - Vec3(reach));
      const std::array<long, 3> c1 = cell_index(hi + Vec3(reach));
      for (long x = c0[0]; x <= c1[0]; ++x) {
        for (long y = c0[1]; y <= c1[1]; ++y) {
          for (long z = c0[2]; z <= c1[2]; ++z) cells.push_back(key_of({x, y, z}));
        }
      }
    }
    std::sort(cells.begin(), cells.end());
    cells.erase(std::unique(cells.begin(), cells.end()), cells.end());
    for (const std::uint64_t key : cells) {
      const auto it = ranges_.find(key);
      if (it == ranges_.end()) continue;
      for (int i = it->second.first; i < it->second.second; ++i) visit(sorted_[i]);
    }
  }

 private:
  std::array<long, 3> cell_index(const Vec3& p) const {
    return {static_cast<long>(std::floor((p[0] - origin_[0]) / cell_)),
            static_cast<long>(std::floor((p[1] - origin_[1]) / cell_)),
            static_cast<long>(std::floor((p[2] - origin_[2]) / cell_))};
  }

  static std::uint64_t key_of(const std::array<long, 3>& c) {
    // 21 bits per axis; the cell size keeps indices well inside that range,
    // and neighbours one cell outside (-1) wrap harmlessly to distinct keys.
    constexpr std::uint64_t kMask = (std::uint64_t{1} << 21) - 1;
    return ((static_cast<std::uint64_t>(c[0]) & kMask) << 42) |
           ((static_cast<std::uint64_t>(c[1]) & kMask) << 21) | (static_cast<std::uint64_t>(c[2]) & kMask);
  }

  Vec3 origin_;
  double cell_;
  std::vector<int> sorted_;
  std::unordered_map<std::uint64_t, std::pair<int, int>> ranges_;
};

}  // namespace

std::vector<Violation> check_conforming_mesh(const RawMesh& mesh, const ConformingCheckOptions& options) {
  Report report;
  const auto& points = mesh.points;
  const auto& faces = mesh.faces;
  const int n_points = static_cast<int>(points.size());

  // --- per-vertex values -----------------------------------------------------
  std::vector<char> finite_point(points.size(), 1);
  for (int v = 0; v < n_points; ++v) {
    if (!finite(points[v])) {
      finite_point[v] = 0;
      report.add("non-finite-coordinate", vertex_at(v), "position " + format_point(points[v]));
    }
  }
  if (!mesh.radiance.empty()) {
    if (mesh.radiance.size() != points.size()) {
      report.add("radiance-count", "mesh",
                 std::to_string(mesh.radiance.size()) + " radiance values for " + std::to_string(points.size()) +
                     " vertices");
    } else {
      for (int v = 0; v < n_points; ++v) {
        const Rgb& r = mesh.radiance[v];
        if (!finite(r)) {
          report.add("non-finite-radiance", vertex_at(v), "radiance " + format_point(r));
        } else if (r[0] < 0.0 || r[1] < 0.0 || r[2] < 0.0) {
          report.add("negative-radiance", vertex_at(v), "radiance " + format_point(r));
        }
      }
    }
  }

  // --- per-face structure ----------------------------------------------------
  // usable: enters the topology checks; geometric: also has finite corners.
  std::vector<char> usable(faces.size(), 0);
  std::vector<char> geometric(faces.size(), 0);
  for (std::size_t f = 0; f < faces.size(); ++f) {
    const auto& fv = faces[f];
    if (fv.size() < 3) {
      report.add("face-size", face_at(f), "has " + std::to_string(fv.size()) + " vertices, needs at least 3");
      continue;
    }
    bool in_range = true;
    for (int v : fv) {
      if (v < 0 || v >= n_points) {
        report.add("index-out-of-range", face_at(f),
                   "vertex index " + std::to_string(v) + " not in [0, " + std::to_string(n_points) + ")");
        in_range = false;
        break;
      }
    }
    if (!in_range) continue;
    int repeated = -1;
    if (fv.size() == 3) {
      if (fv[0] == fv[1] || fv[0] == fv[2]) repeated = fv[0];
      else if (fv[1] == fv[2]) repeated = fv[1];
    } else {
      std::vector<int> sorted = fv;
      std::sort(sorted.begin(), sorted.end());
      const auto it = std::adjacent_find(sorted.begin(), sorted.end());
      if (it != sorted.end()) repeated = *it;
    }
    if (repeated >= 0) {
      report.add("repeated-vertex", face_at(f), "uses vertex " + std::to_string(repeated) + " more than once");
      continue;
    }
    usable[f] = 1;
    geometric[f] = std::all_of(fv.begin(), fv.end(), [&](int v) { return finite_point[v] != 0; });
  }

  // Tolerance from the extent of what the faces span (docs/design.md §6: relative,
  // so the check does not depend on scene units).
  Vec3 lo(std::numeric_limits<double>::max());
  Vec3 hi(-std::numeric_limits<double>::max());
  bool any_geometry = false;
  for (std::size_t f = 0; f < faces.size(); ++f) {
    if (!geometric[f]) continue;
    for (int v : faces[f]) {
      lo.minimize(points[v]);
      hi.maximize(points[v]);
      any_geometry = true;
    }
  }
  const double diagonal = any_geometry ? (hi - lo).norm() : 0.0;
  const double tolerance = options.relative_tolerance * diagonal;

  // --- degenerate faces ------------------------------------------------------
  for (std::size_t f = 0; f < faces.size(); ++f) {
    if (!geometric[f]) continue;
    const auto& fv = faces[f];
    // Newell's vector: twice the (projected) area of a polygon, exact for triangles.
    Vec3 twice_area(0.0);
    double longest = 0.0;
    for (std::size_t i = 0; i < fv.size(); ++i) {
      const Vec3& p = points[fv[i]];
      const Vec3& q = points[fv[(i + 1) % fv.size()]];
      twice_area += OpenMesh::cross(p, q);
      longest = std::max(longest, (q - p).norm());
    }
    // Smallest altitude of a triangle = 2A / longest edge: the face is flat
    // when some vertex lies within tolerance of the line through its opposite edge.
    const double altitude = longest > 0.0 ? twice_area.norm() / longest : 0.0;
    if (altitude <= tolerance) {
      char buf[128];
      std::snprintf(buf, sizeof buf, "area %.3g, smallest height %.3g <= tolerance %.3g",
                    0.5 * twice_area.norm(), altitude, tolerance);
      report.add("degenerate-face", face_at(f), buf);
    }
  }

  // --- duplicated faces (same vertex set) ----------------------------------
  {
    // Sort by a hash of the sorted vertex list, then compare lists only
    // within equal hashes: no per-face allocation kept alive for 1e6 faces.
    auto sorted_vertices = [&](std::size_t f) {
      std::vector<int> key = faces[f];
      std::sort(key.begin(), key.end());
      return key;
    };
    std::vector<std::pair<std::uint64_t, std::size_t>> hashed;
    hashed.reserve(faces.size());
    for (std::size_t f = 0; f < faces.size(); ++f) {
      if (!usable[f]) continue;
      std::uint64_t h = 1469598103934665603ull;  // FNV-1a over the sorted indices
      for (int v : sorted_vertices(f)) {
        h ^= static_cast<std::uint32_t>(v);
        h *= 1099511628211ull;
      }
      hashed.emplace_back(h, f);
    }
    std::sort(hashed.begin(), hashed.end());
    for (std::size_t i = 0; i < hashed.size();) {
      std::size_t j = i + 1;
      while (j < hashed.size() && hashed[j].first == hashed[i].first) ++j;
      for (std::size_t u = i + 1; u < j; ++u) {
        const std::vector<int> key = sorted_vertices(hashed[u].second);
        for (std::size_t w = i; w < u; ++w) {
          if (!usable[hashed[w].second] || sorted_vertices(hashed[w].second) != key) continue;
          report.add("duplicate-face", face_at(hashed[u].second),
                     "same vertices as face " + std::to_string(hashed[w].second));
          // A copy would also count as a second face on each of its edges;
          // the duplicate report already says what is wrong.
          usable[hashed[u].second] = 0;
          geometric[hashed[u].second] = 0;
          break;
        }
      }
      i = j;
    }
  }

  // --- edges: manifold, orientation, boundary --------------------------------
  std::vector<int> corner_offset(faces.size() + 1, 0);
  for (std::size_t f = 0; f < faces.size(); ++f) {
    corner_offset[f + 1] = corner_offset[f] + (usable[f] ? static_cast<int>(faces[f].size()) : 0);
  }
  std::vector<EdgeUse> uses;
  uses.reserve(corner_offset.back());
  for (std::size_t f = 0; f < faces.size(); ++f) {
    if (!usable[f]) continue;
    const auto& fv = faces[f];
    const int k = static_cast<int>(fv.size());
    for (int i = 0; i < k; ++i) {
      const int a = fv[i];
      const int b = fv[(i + 1) % k];
      const int ca = corner_offset[f] + i;
      const int cb = corner_offset[f] + (i + 1) % k;
      uses.push_back(EdgeUse{edge_key(a, b), static_cast<int>(f), a < b ? ca : cb, a < b ? cb : ca, a < b});
    }
  }
  std::sort(uses.begin(), uses.end(), [](const EdgeUse& x, const EdgeUse& y) {
    return x.key != y.key ? x.key < y.key : x.face < y.face;
  });

  UnionFind fans(corner_offset.back());
  std::vector<std::pair<int, int>> boundary;  // (edge use index, face) of edges with one face
  for (std::size_t i = 0; i < uses.size();) {
    std::size_t j = i;
    while (j < uses.size() && uses[j].key == uses[i].key) ++j;
    const int a = static_cast<int>(uses[i].key >> 32);
    const int b = static_cast<int>(uses[i].key & 0xffffffffu);
    const std::size_t count = j - i;
    if (count == 1) {
      boundary.emplace_back(static_cast<int>(i), uses[i].face);
    } else if (count > 2) {
      std::string list;
      for (std::size_t u = i; u < j && u < i + 6; ++u) list += (u == i ? "" : ", ") + std::to_string(uses[u].face);
      if (count > 6) list += ", ...";
      report.add("non-manifold-edge", edge_at(a, b), "shared by " + std::to_string(count) + " faces (" + list + ")");
    } else if (uses[i].forward == uses[i + 1].forward) {
      report.add("orientation", edge_at(a, b),
                 "faces " + std::to_string(uses[i].face) + " and " + std::to_string(uses[i + 1].face) +
                     " both run it from vertex " + std::to_string(uses[i].forward ? a : b) +
                     " (one of them is flipped)");
    }
    // Faces across an edge belong to the same fan at both its ends.
    for (std::size_t u = i + 1; u < j; ++u) {
      fans.unite(uses[i].corner_lo, uses[u].corner_lo);
      fans.unite(uses[i].corner_hi, uses[u].corner_hi);
    }
    i = j;
  }

  // --- T-junction cracks inside a connected component -----------------------
  // docs/design.md §3: surfaces meet with coincident but distinct vertices, so only a
  // vertex of the edge's own component (linked by shared indices) is a crack.
  if (!boundary.empty() && diagonal > 0.0) {
    UnionFind components(points.size());
    std::vector<char> used(points.size(), 0);
    for (std::size_t f = 0; f < faces.size(); ++f) {
      if (!usable[f]) continue;
      for (int v : faces[f]) {
        components.unite(faces[f][0], v);
        if (geometric[f]) used[v] = 1;  // inside the bounding box the grid covers
      }
    }
    std::vector<int> candidates;
    std::vector<int> component_of(points.size());
    for (int v = 0; v < n_points; ++v) {
      component_of[v] = components.find(v);
      if (used[v]) candidates.push_back(v);
    }
    // Cells about one edge long keep both the vertices per cell and the cells
    // per edge small; never finer than the tolerance nor than 2^20 per axis.
    double total_length = 0.0;
    std::size_t n_lengths = 0;
    for (const EdgeUse& u : uses) {
      if (!geometric[u.face]) continue;
      total_length += (points[u.key >> 32] - points[u.key & 0xffffffffu]).norm();
      ++n_lengths;
    }
    double cell = n_lengths > 0 ? total_length / static_cast<double>(n_lengths) : diagonal;
    cell = std::max({cell, 2.0 * tolerance, diagonal / static_cast<double>(1 << 20)});
    const VertexGrid grid(points, candidates, lo - Vec3(cell), cell);

    // Joins `corner` (of vertex `end`) with the fan of the one face that
    // has boundary edge (end, other), if there is such a face.
    const auto glue_fan = [&](int corner, int end, int other) {
      const std::uint64_t key = edge_key(end, other);
      const auto it = std::lower_bound(uses.begin(), uses.end(), key,
                                       [](const EdgeUse& u, std::uint64_t k) { return u.key < k; });
      if (it == uses.end() || it->key != key) return;
      if (std::next(it) != uses.end() && std::next(it)->key == key) return;
      fans.unite(corner, end < other ? it->corner_lo : it->corner_hi);
    };
    std::vector<int> hits;
    std::vector<std::uint64_t> cells;
    for (const auto& [use_index, face] : boundary) {
      if (!geometric[face]) continue;
      const int a = static_cast<int>(uses[use_index].key >> 32);
      const int b = static_cast<int>(uses[use_index].key & 0xffffffffu);
      const Vec3& pa = points[a];
      const Vec3& pb = points[b];
      const Vec3 ab = pb - pa;
      const double length2 = ab.sqrnorm();
      if (std::sqrt(length2) <= 2.0 * tolerance) continue;  // no room strictly inside
      const int component = component_of[a];
      hits.clear();
      grid.near_segment(pa, pb, tolerance, cells, [&](int v) {
        if (component_of[v] != component || v == a || v == b) return;
        const Vec3& p = points[v];
        if ((p - pa).norm() <= tolerance || (p - pb).norm() <= tolerance) return;
        const double t = OpenMesh::dot(p - pa, ab) / length2;
        if (t <= 0.0 || t >= 1.0) return;
        if ((pa + ab * t - p).norm() > tolerance) return;
        hits.push_back(v);
      });
      std::sort(hits.begin(), hits.end());
      hits.erase(std::unique(hits.begin(), hits.end()), hits.end());
      for (int v : hits) {
        report.add("t-junction", vertex_at(v),
                   "lies inside boundary " + edge_at(a, b) + " of face " + std::to_string(face) +
                       " in its own component (crack)");
      }
      if (hits.empty()) continue;
      // Closing the crack would join the faces along a-b with those along
      // a-v...-b; glue their fans at a and b so the crack is not reported a
      // second time as non-manifold vertices at the ends of the edge.
      const auto t_of = [&](int v) { return OpenMesh::dot(points[v] - pa, ab); };
      const auto [nearest_a, nearest_b] = std::minmax_element(
          hits.begin(), hits.end(), [&](int x, int y) { return t_of(x) < t_of(y); });
      glue_fan(uses[use_index].corner_lo, a, *nearest_a);
      glue_fan(uses[use_index].corner_hi, b, *nearest_b);
    }
  }

  // --- non-manifold vertices: more than one fan of faces around a vertex ----
  {
    std::vector<int> first_fan(points.size(), -1);
    std::vector<int> fan_count(points.size(), 0);
    for (std::size_t f = 0; f < faces.size(); ++f) {
      if (!usable[f]) continue;
      for (std::size_t i = 0; i < faces[f].size(); ++i) {
        const int v = faces[f][i];
        const int root = fans.find(corner_offset[f] + static_cast<int>(i));
        if (first_fan[v] < 0) {
          first_fan[v] = root;
          fan_count[v] = 1;
        } else if (first_fan[v] != root && fan_count[v] == 1) {
          fan_count[v] = 2;
        }
      }
    }
    for (int v = 0; v < n_points; ++v) {
      if (fan_count[v] > 1) {
        report.add("non-manifold-vertex", vertex_at(v), "its faces form separate fans that meet only at this vertex");
      }
    }
  }

  return report.take();
}

std::string format_violation(const Violation& v) { return v.kind + " at " + v.where + ": " + v.detail; }

}  // namespace lhr
