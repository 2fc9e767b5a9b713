#include "radiosity/receiver_oracle.hpp"

#include <algorithm>
#include <cmath>

namespace lhr {

namespace {

// Lines this close to parallel (sin² of their angle) have no useful crossing.
constexpr double kParallelSin2 = 1e-6;
// A crossing farther out than this along either segment (in units of its
// length, 0 and 1 its ends) makes weights of several times the paper's: a
// pair that badly shaped is left to the paper's formula.
constexpr double kCrossingReach = 4.0;

// B_min: the smallest radiance of the four vertices without S.
double radiance_without_shooter(const EdgeValues& edge) {
  double b_min = edge.total[0] - edge.own[0];
  for (int i = 1; i < 4; ++i) b_min = std::min(b_min, edge.total[i] - edge.own[i]);
  return std::max(0.0, b_min);
}

}  // namespace

std::array<double, 4> edge_weights(const Vec3& p1, const Vec3& p2, const Vec3& p3, const Vec3& p4) {
  constexpr std::array<double, 4> kPaper{1.0, 1.0, -1.0, -1.0};
  // α a − β b = c, with a = p1 − p2, b = p3 − p4, c = p4 − p2, solved by
  // least squares (exactly, for a planar pair).
  const Vec3 a = p1 - p2, b = p3 - p4, c = p4 - p2;
  const double aa = OpenMesh::dot(a, a), bb = OpenMesh::dot(b, b), ab = OpenMesh::dot(a, b);
  const double ac = OpenMesh::dot(a, c), bc = OpenMesh::dot(b, c);
  const double det = aa * bb - ab * ab;
  if (!(det > kParallelSin2 * aa * bb)) return kPaper;
  const double alpha = (bb * ac - ab * bc) / det;
  const double beta = (ab * ac - aa * bc) / det;
  const auto reachable = [](double t) { return t > -kCrossingReach && t < 1.0 + kCrossingReach; };
  if (!reachable(alpha) || !reachable(beta)) return kPaper;
  return {2.0 * alpha, 2.0 * (1.0 - alpha), -2.0 * beta, -2.0 * (1.0 - beta)};
}

void oracle_edges(const InteractionGraph& graph, const SurfaceHierarchy& receiver, NodeId leaf,
                  std::vector<OracleEdge>& out) {
  const auto& c = receiver.corners(leaf);
  for (int k = 0; k < 3; ++k) {
    if (receiver.is_boundary_edge(leaf, k)) continue;
    // The graph leaf across: the same-level one (each pair once, from the
    // smaller id), or a coarser one, which only this side sees. A finer side
    // lists the pair itself.
    NodeId same_level = receiver.neighbor(leaf, k);
    if (same_level == kNoNode && receiver.parent(leaf) != kNoNode) {
      same_level = receiver.neighbor(receiver.parent(leaf), k);
    }
    if (same_level == kNoNode) continue;
    const NodeId across = graph.leaf_containing(same_level, receiver);
    if (across == kNoNode || (across == same_level && receiver.level(across) == receiver.level(leaf) && across < leaf)) {
      continue;
    }
    OracleEdge edge;
    edge.left = leaf;
    edge.right = across;
    edge.vertex = {c[k], c[(k + 1) % 3], c[(k + 2) % 3], kNoVertex};
    const Vec3 p1 = receiver.point(c[k]), along = receiver.point(c[(k + 1) % 3]) - p1;
    double farthest = -1.0;
    for (VertexId v : receiver.corners(across)) {
      const double d = OpenMesh::cross(along, receiver.point(v) - p1).sqrnorm();
      if (d > farthest) {
        farthest = d;
        edge.vertex[3] = v;
      }
    }
    out.push_back(edge);
  }
}

bool ReceiverOracle::edge_refines(const EdgeValues& edge, double pixels, double eps_pixel) const {
  const auto& b = edge.own;
  if (b[0] == b[1] && b[0] == b[2] && b[0] == b[3]) return refines(0.0, pixels, eps_pixel);
  double sum = 0.0, magnitude = 0.0;
  for (double w : edge.weights) {
    sum += w;
    magnitude += std::abs(w);
  }
  if (std::abs(edge.visibility_1 - edge.visibility_2) < vis_threshold_) {
    const double b_min = radiance_without_shooter(edge);
    const auto [lo, hi] = std::minmax_element(b.begin(), b.end());
    const double m_lo = tone_.display(b_min + *lo), m_hi = tone_.display(b_min + *hi);
    // Σ w_i M_i = Σ w_i (M_i − M_lo) + M_lo Σ w_i, the first term between
    // −N and P times M_hi − M_lo (P, N: the weights' positive and negative
    // parts). Σ w_i is 0 but for rounding; what rounding adds to ΔE's own
    // sum is covered by the last term, far above it.
    const double positive = 0.5 * (magnitude + sum), negative = 0.5 * (magnitude - sum);
    const double bound =
        0.5 * (std::max(positive, negative) * (m_hi - m_lo) + std::abs(sum) * m_lo + 1e-12 * magnitude * m_hi);
    if (bound * pixels < eps_pixel) return false;
  }
  return refines(display_error(edge), pixels, eps_pixel);
}

double ReceiverOracle::display_error(const EdgeValues& edge) const {
  // S gives the four vertices the same (mostly: nothing, where it is hidden
  // from all of them): no second difference and no visibility change can
  // show, and the tone map, the oracle's cost, need not be evaluated.
  const auto& b = edge.own;
  if (b[0] == b[1] && b[0] == b[2] && b[0] == b[3]) return 0.0;
  const double b_min = radiance_without_shooter(edge);
  const auto shown = [&](double value) { return tone_.display(b_min + value); };
  if (std::abs(edge.visibility_1 - edge.visibility_2) < vis_threshold_) {
    double sum = 0.0;
    for (int i = 0; i < 4; ++i) sum += edge.weights[i] * shown(b[i]);
    return 0.5 * std::abs(sum);
  }
  const auto [lo, hi] = std::minmax_element(b.begin(), b.end());
  return shown(*hi) - shown(*lo);
}

}  // namespace lhr
