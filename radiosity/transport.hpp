#pragma once
// Transport coefficients of the linear basis (paper §3, docs/design.md §4 "Linear
// basis, point collocation"): from a shooter triangle j to a receiver node x,
//   F^l(x,j) = ∫_Tj N_j^l(y) cosθx cosθy V(x,y) / (π r²) dA_y,   l = 0,1,2.
// Σ_l F^l without V is the exact point-to-triangle form factor (Lambert's
// contour formula); basis-weighted Embree samples give the split among l and
// the occlusion, as a ratio to the unoccluded kernel at the same samples so
// that an unoccluded link reproduces the exact form factor.

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "mesh/types.hpp"
#include "radiosity/ray_caster.hpp"

namespace lhr {

struct TransportCoefficients {
  std::array<float, 3> f{0.0f, 0.0f, 0.0f};  // F^l, occluded; a constant-basis shooter uses f[0] only
  float unoccluded = 0.0f;                    // exact Σ_l F^l with V = 1
  float visible() const { return f[0] + f[1] + f[2]; }
};

// A collocation point. `approach` is a unit direction in the tangent plane
// toward the receiver's interior (zero if none): a node on a shooter's plane
// or edge (a floor vertex in a wall–floor corner) takes the limit from there.
struct ReceiverPoint {
  Vec3 x;
  Vec3 normal;
  Vec3 approach{0, 0, 0};
};

struct TransportSampling {
  int k = 4;              // k² stratified samples per shooter triangle
  std::uint64_t key = 0;  // sample pattern, from the link's ids (deterministic)
};

// What both draws of one link share (its exact form factors, the weights its
// shadow rays are drawn and weighed by, a near triangle's basis split)
// depends on the receiver point and the shooter alone; each draw takes its
// own rays. While a scope is open on a thread, each transport function works
// that out once per receiver point and reuses it for the link's further
// draws: the same numbers, not computed twice. A first link and a partly
// hidden one are drawn twice (LinearSolver::compute_coefficients, which opens
// a scope per link). Every call inside one scope must be for one shooter;
// a scope opened inside another starts empty.
class SharedLinkGeometry {
 public:
  SharedLinkGeometry();
  ~SharedLinkGeometry();
  SharedLinkGeometry(const SharedLinkGeometry&) = delete;
  SharedLinkGeometry& operator=(const SharedLinkGeometry&) = delete;

 private:
  std::size_t outer_base_;
};

// A linear-basis shooter triangle's coefficients from its four children's,
// in mesh/hierarchy.hpp's child order: each of the parent's hat functions is
// linear over each child, so F_P^L = Σ_c Σ_l N_P^L(corner l of child c) F_c^l
// holds exactly, occlusion included, with no new rays (docs/design.md,
// "Coarsening links").
TransportCoefficients merge_child_coefficients(const std::array<TransportCoefficients, 4>& children);

// Linear-basis shooter triangle (corners counter-clockwise seen from its front).
TransportCoefficients triangle_transport(const ReceiverPoint& receiver, const std::array<Vec3, 3>& shooter,
                                         const RayCaster& rays, const TransportSampling& sampling,
                                         std::uint64_t& ray_count);

// Per triangle of a surface that shoots as a constant-basis cluster, what
// its transport evaluates at every link and no receiver changes: computed
// once per surface, where recomputing them and copying the corners out of
// the mesh at each link took a tenth of a coarse solve's time.
struct ShooterTriangleTable {
  ShooterTriangleTable() = default;
  explicit ShooterTriangleTable(std::span<const std::array<Vec3, 3>> triangles);
  std::size_t size() const { return corner.size(); }
  std::size_t bytes() const;

  std::vector<std::array<Vec3, 3>> corner;
  std::vector<Vec3> normal;    // unit, from the corners
  std::vector<Vec3> centroid;  // the corners' mean
  std::vector<double> area;
  std::vector<double> size2;  // longest edge, squared
};

// One shooter's triangles: `members` of a table, in that order, or the whole
// table when `members` is empty.
struct ShooterTriangles {
  const ShooterTriangleTable* table = nullptr;
  std::span<const std::int32_t> members;
  std::size_t size() const { return members.empty() ? table->size() : members.size(); }
  // Row of the table that triangle j of this shooter is.
  std::size_t row(std::size_t j) const { return members.empty() ? j : static_cast<std::size_t>(members[j]); }
};

// What the triangles of a constant-basis shooter hold, so that a link
// carries what its receiver sees of them rather than their mean
// (docs/accuracy.md, "A bright part that sees more"): per triangle its mean
// luminance, and the mean the shooter carries. The link's f[0] is then
// Σ_j F_j V_j value_j / carried (V_j: how much of triangle j the receiver
// sees, from the shadow rays; docs/accuracy.md, "What a table hides").
// `value` is per row of the shooter's ShooterTriangleTable.
struct ShooterShape {
  std::span<const double> value;
  double carried = 0.0;
};

// Constant-basis shooter made of several triangles (a root cluster): f[0] is
// the exact form factor of all of them times the share of its shadow rays
// that arrive, the rays drawn in proportion to each triangle's share of it
// and within each triangle in proportion to the kernel (each part weighed by
// its value when `shape` is given). `corner_edges`, when given, names the
// table's triangles' edges (shared_edge_form_factors, per row): the same
// form factors, each shared edge integrated once.
TransportCoefficients cluster_transport(const ReceiverPoint& receiver, const ShooterTriangles& shooter,
                                        const RayCaster& rays, const TransportSampling& sampling,
                                        std::uint64_t& ray_count, const ShooterShape* shape = nullptr,
                                        std::span<const std::array<std::int32_t, 3>> corner_edges = {});
// The same for triangles given as corners (each call builds their table).
TransportCoefficients cluster_transport(const ReceiverPoint& receiver,
                                        std::span<const std::array<Vec3, 3>> shooter, const RayCaster& rays,
                                        const TransportSampling& sampling, std::uint64_t& ray_count,
                                        const ShooterShape* shape = nullptr);

// A whole planar surface as one constant-basis shooter: f[0] is the exact
// form factor of its input polygons times the weighted share of its shadow
// rays that arrive, the rays drawn to its triangles in proportion to each
// one's form factor (exact near the receiver, a disc estimate farther off; a
// cluster whose outline cannot give its form factor uses exact ones) and
// within each in proportion to the kernel. Drawing by area and weighting by
// the kernel instead lets the few samples nearest a receiver in a corner
// decide the whole fraction (the kernel grows as 1/r⁴ there), which
// misjudged a floor seen from the foot of a wall by 30 % (docs/accuracy.md).
TransportCoefficients surface_transport(const ReceiverPoint& receiver, std::span<const std::vector<Vec3>> polygons,
                                        const ShooterTriangles& triangles, const RayCaster& rays,
                                        const TransportSampling& sampling, std::uint64_t& ray_count,
                                        const ShooterShape* shape = nullptr);
TransportCoefficients surface_transport(const ReceiverPoint& receiver, std::span<const std::vector<Vec3>> polygons,
                                        std::span<const std::array<Vec3, 3>> triangles, const RayCaster& rays,
                                        const TransportSampling& sampling, std::uint64_t& ray_count,
                                        const ShooterShape* shape = nullptr);

// How a planar shooter's triangles lie against the receiver's horizon,
// which decides how its shadow rays are drawn among them:
// - kUnknown: some may lie across or below it; rays are drawn by estimates
//   widened so that no triangle across it is left out, and each counts for
//   its triangle's own estimate over the one it was drawn by;
// - kAbove: every triangle lies above it (the caller knows); rays are drawn
//   by the unwidened estimates, which only add noise where none crosses;
// - kCrossing: the shooter reaches below it (its form factor was clipped);
//   each triangle is judged by its corners: above, its estimate; across,
//   its exact clipped form factor; below, nothing.
enum class ShooterHorizon { kUnknown, kAbove, kCrossing };

// Running sums, over a planar shooter's triangles in order, of the cheap
// stand-ins for their form factors from x that cluster links draw shadow
// rays by: a disc's beyond two triangle sizes, the exact value within
// (planar_shooter_transport's weights for a shooter wholly above x's
// horizon). Cleared and refilled.
void drawing_form_factor_sums(const Vec3& x, const Vec3& n, const ShooterTriangles& triangles,
                              std::vector<double>& sums);

// The same for any planar constant-basis shooter whose exact unoccluded form
// factor `ff` from the receiver is known (a cluster's, from its outline):
// shadow rays drawn by disc_form_factors, as `horizon` says.
TransportCoefficients planar_shooter_transport(const ReceiverPoint& receiver, double ff,
                                               const ShooterTriangles& triangles, const RayCaster& rays,
                                               const TransportSampling& sampling, std::uint64_t& ray_count,
                                               const ShooterShape* shape, ShooterHorizon horizon);

// The same for a cluster of a curved shooter (`triangles`, its roots) when
// x sees every one of them plainly: its exact form factor is then the
// contour integral of its `outline` (edges of `points`, as for
// outline_form_factor), and each root's disc estimate takes the root's own
// normal (docs/design.md, "Cluster outlines"). nullopt where some root is
// not seen plainly or there is no outline: the caller takes the roots one by
// one (cluster_transport).
std::optional<TransportCoefficients> curved_cluster_transport(
    const ReceiverPoint& receiver, const ShooterTriangles& triangles, std::span<const Vec3> points,
    std::span<const std::array<std::int32_t, 2>> outline, const RayCaster& rays, const TransportSampling& sampling,
    std::uint64_t& ray_count, const ShooterShape* shape);

}  // namespace lhr
