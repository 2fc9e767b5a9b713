#pragma once
// The path-traced reference at the vertices of an exported mesh (docs/design.md §5
// "How accuracy is judged": the mesh is the product, so it is measured
// directly and not only through one camera). Each vertex gets an unbiased
// estimate of the radiance leaving it, L(x) = Le(x) + ρ(x)/π·E(x), on its
// own surface's side: a vertex on a crease or in a corner belongs to one
// surface (docs/design.md §3) and takes the limit from inside that surface.

#include <functional>
#include <vector>

#include "mesh/export_mesh.hpp"
#include "mesh/validate.hpp"
#include "render/path_tracer.hpp"
#include "render/solution_view.hpp"

namespace lhr {

struct VertexReference {
  std::vector<Rgb> radiance;             // per vertex, scene units
  std::vector<double> standard_error;    // per vertex: of the mean luminance, from the sample variance
  int spp = 0;
  int rounds = 0;
  // RMS of the per-vertex standard errors, and that over the mean luminance.
  double noise_rms = 0.0;
  double noise = 0.0;
  double mean_luminance = 0.0;
};

// mesh: triangles (as `lhr solve` exports them), counter-clockwise seen from
// their front. A vertex's front is the area-weighted normal of its faces;
// its paths start from the point nudged into its widest-angled face that
// is not inside a closed object (a vertex on the foot of a box standing on
// a floor takes the limit from the floor around the box).
// options: spp, seed, target_noise, max_spp and checkpoint as for images
// (jitter does not apply; checkpoint is called before each vertex and every
// 1024 samples); sample s of vertex v uses the random numbers of
// key (seed, v, s), so the result does not depend on the thread count and
// rounds give what one run at the final count gives. progress is called
// from worker threads, one call at a time.
// Throws std::invalid_argument naming the face or vertex when a face is not
// a triangle of distinct in-range vertices, a vertex belongs to no face, or
// a vertex lies on no front-facing surface of the scene.
VertexReference trace_vertex_reference(const PathTracer& tracer, const RawMesh& mesh, const PathTraceOptions& options,
                                       const std::function<void(const PathTraceProgress&)>& progress = {});

// The reference as a mesh file holds it: mesh's vertices and faces, the
// estimate as radiance, its standard error, and the display colour of the
// estimate under the tone map chosen, its defaults (adaptation, white) taken
// from the luminance of the vertices.
ExportMesh vertex_reference_export(const RawMesh& mesh, const VertexReference& reference, const ToneMapSettings& tone);

}  // namespace lhr
