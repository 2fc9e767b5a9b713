#pragma once
// Unoccluded point-to-polygon form factors (docs/design.md §4 "Linear basis, point
// collocation": Σ_l F^l(x,j) is the exact point-to-triangle form factor).

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "mesh/types.hpp"

namespace lhr {

// Form factor from a differential area at x with unit normal n to a planar
// polygon, without occlusion: ∫ cosθx cosθy / (π r²) dA over the part of the
// polygon above x's tangent plane and seen from its front (vertices
// counter-clockwise seen from the front). Lambert's contour formula.
//
// Receivers on the shooter's plane or boundary (a floor vertex in a
// wall–floor corner) have no value of their own there; the result is the
// limit as x approaches along `approach` (a direction in x's tangent plane,
// e.g. toward the receiver element's interior). Without one, x approaches
// from the shooter's front. Always finite, in [0, 1].
double point_polygon_form_factor(const Vec3& x, const Vec3& n, std::span<const Vec3> polygon,
                                 const Vec3* approach = nullptr);

inline double point_triangle_form_factor(const Vec3& x, const Vec3& n, const std::array<Vec3, 3>& triangle,
                                         const Vec3* approach = nullptr) {
  return point_polygon_form_factor(x, n, std::span<const Vec3>(triangle.data(), 3), approach);
}

// The form factors of triangles that share edges (a cluster of one
// surface's initial triangles) from x, each exactly as
// point_triangle_form_factor gives it. Lambert's term of an edge seen along
// it is minus its term seen against it, so each shared edge is integrated
// once (per thread, a table as long as the largest edge id seen): corner_edge[j][k]
// names the edge from corner k to corner k+1 of triangle j as 2·id, or
// 2·id + 1 where the triangle runs against the edge's own direction (any
// direction, the same for every triangle using it). Triangles that
// need clipping or a limit (x on or near them) take the general path.
// `members`, when given, picks the triangles (and their rows of
// `corner_edge`) out of `triangles`, in its order.
void shared_edge_form_factors(const Vec3& x, const Vec3& n, std::span<const std::array<Vec3, 3>> triangles,
                              std::span<const std::array<std::int32_t, 3>> corner_edge, const Vec3* approach,
                              std::vector<double>& out, std::span<const std::int32_t> members = {});

// Form factor from x of a planar region given only its outline: edges
// (indices into `points`) running counter-clockwise around it seen from its
// front, in any order, holes included. Lambert's contour integral over the
// outline is the sum of the plain contour integrals of any triangulation of
// the region, every inner edge cancelling (docs/design.md, "Cluster
// outlines"). A region reaching below x's tangent plane is clipped to it,
// as each of its triangles would be; `clipped` says whether it was.
// nullopt where some triangle would need a limit: x within a millionth of
// the region's size of its plane, or behind it; also where the outline only
// grazes x's tangent plane, so that its crossings do not pair up.
std::optional<double> outline_form_factor(const Vec3& x, const Vec3& n, const Vec3& plane_normal,
                                          std::span<const Vec3> points,
                                          std::span<const std::array<std::int32_t, 2>> outline,
                                          bool* clipped = nullptr);

// The contour integral of an outline as for outline_form_factor, with no
// check: the form factor of a surface of triangles that share edges, planar
// or not, only where x sees every triangle plainly (open_outline_form_factor
// says what that is and checks it).
double outline_contour_form_factor(const Vec3& x, const Vec3& n, std::span<const Vec3> points,
                                   std::span<const std::array<std::int32_t, 2>> outline);

// Form factor from x of a surface of triangles that share edges, planar or
// not, given its outline as for outline_form_factor. Where every triangle is
// seen plainly (x clear of its plane, in front of it, and the triangle wholly
// above x's tangent plane), each triangle's form factor is its contour
// integral and the inner edges cancel whatever the angle between their
// triangles, so the sum is the outline's contour integral: the cost of the
// outline, not of the triangles' edges (docs/design.md, "Cluster outlines").
// nullopt where some triangle is not seen plainly: the caller then takes
// them one by one.
std::optional<double> open_outline_form_factor(const Vec3& x, const Vec3& n,
                                               std::span<const std::array<Vec3, 3>> triangles,
                                               std::span<const Vec3> points,
                                               std::span<const std::array<std::int32_t, 2>> outline);

}  // namespace lhr
