#pragma once
// How close a mesh's vertex radiance is to a path-traced reference at the
// same vertices (docs/design.md §5 "How accuracy is judged": the per-vertex relative
// error of the exported mesh). Per vertex the relative luminance error
// |Y − Y_ref| / max(Y_ref, floor), the floor being 1 % of the mean Y_ref so
// that vertices in shadow do not turn noise into huge relative errors.

#include <cstddef>
#include <vector>

#include "mesh/validate.hpp"

namespace lhr {

struct VertexMetrics {
  std::size_t vertices = 0;
  double floor = 0.0;        // 1 % of the mean reference luminance
  double p50 = 0.0;          // median relative error
  double p95 = 0.0;
  double max = 0.0;
  std::size_t worst_vertex = 0;  // where the maximum is
  double within_10 = 0.0;    // % of vertices with relative error ≤ 0.10
  double within_15 = 0.0;    // % of vertices with relative error ≤ 0.15
  double mean_ratio = 0.0;   // ΣY / ΣY_ref (1: no overall bias); +inf when ΣY_ref = 0 < ΣY
  // When the reference carries standard errors: the median of the standard
  // error over the same denominator (its noise in the units of p50), and the
  // % of vertices off by more than 3 standard errors (with an unbiased mesh
  // and Gaussian noise, about 0.3 %), which tells bias from noise.
  bool has_noise = false;
  double noise_p50 = 0.0;
  double beyond_3_sigma = 0.0;
};

// Quantile q in [0,1] of values by linear interpolation between order
// statistics; 0 for no values.
double quantile(std::vector<double> values, double q);

// The vertex sets must match: same count, and each vertex at the same place
// within relative_tolerance of the reference's bounding-box diagonal (both
// files store float coordinates of the same mesh). Throws
// std::invalid_argument with a one-line message otherwise, or when either
// has no radiance.
VertexMetrics compare_vertex_radiance(const RawMesh& mesh, const RawMesh& reference,
                                      double relative_tolerance = 1e-6);

}  // namespace lhr
