#include "render/gouraud.hpp"

#include <tbb/parallel_for.h>

#include <stdexcept>

#include "radiosity/ray_caster.hpp"
#include "render/camera_rays.hpp"

namespace lhr {

std::vector<std::uint8_t> PixelHits::mask() const {
  std::vector<std::uint8_t> m(pixels.size());
  for (std::size_t i = 0; i < pixels.size(); ++i) m[i] = pixels[i].surface >= 0 ? 1 : 0;
  return m;
}

PixelHits trace_pixels(const Camera& camera, const std::vector<const TriMesh*>& meshes) {
  PixelHits hits;
  hits.width = camera.width;
  hits.height = camera.height;
  hits.pixels.resize(static_cast<std::size_t>(camera.width) * camera.height);
  if (meshes.empty()) return hits;
  const RayCaster scene(meshes);
  const CameraRays rays(camera);
  // Each pixel is written once by its own ray: the result does not depend on
  // the thread count.
  tbb::parallel_for(0, camera.height, [&](int y) {
    for (int x = 0; x < camera.width; ++x) {
      const Vec3 direction = rays.direction(x, y);
      const auto hit = scene.intersect(rays.origin(), direction);
      if (!hit) continue;
      const TriMesh& mesh = *meshes[hit->surface];
      Vec3 corner[3];
      int k = 0;
      for (const auto vh : mesh.fv_range(mesh.face_handle(hit->face))) corner[k++] = mesh.point(vh);
      const Vec3 front = OpenMesh::cross(corner[1] - corner[0], corner[2] - corner[0]);
      hits.pixels[static_cast<std::size_t>(y) * camera.width + x] = {
          hit->surface, hit->face, static_cast<float>(hit->u), static_cast<float>(hit->v),
          !(OpenMesh::dot(front, direction) < 0)};
    }
  });
  return hits;
}

std::vector<ViewSample> view_samples(const Camera& camera, const std::vector<const TriMesh*>& meshes) {
  std::vector<ViewSample> view;
  for (const PixelHits::Hit& h : trace_pixels(camera, meshes).pixels) {
    if (h.surface >= 0 && !h.back) view.push_back({h.surface, h.face, h.u, h.v});
  }
  return view;
}

Image shade_gouraud(const PixelHits& hits, const std::vector<const TriMesh*>& meshes,
                    const std::vector<const std::vector<Rgb>*>& values) {
  if (values.size() != meshes.size()) throw std::invalid_argument("shade_gouraud: one value list per mesh");
  Image image(hits.width, hits.height);
  tbb::parallel_for(std::size_t{0}, hits.pixels.size(), [&](std::size_t i) {
    const PixelHits::Hit& h = hits.pixels[i];
    if (h.surface < 0 || h.back) return;
    const TriMesh& mesh = *meshes[h.surface];
    const std::vector<Rgb>& vertex_values = *values[h.surface];
    int corner[3], k = 0;
    for (const auto vh : mesh.fv_range(mesh.face_handle(h.face))) corner[k++] = vh.idx();
    const double w0 = 1.0 - h.u - h.v;
    const Rgb value = w0 * vertex_values[corner[0]] + static_cast<double>(h.u) * vertex_values[corner[1]] +
                      static_cast<double>(h.v) * vertex_values[corner[2]];
    for (int c = 0; c < 3; ++c) image.rgb[3 * i + c] = static_cast<float>(value[c]);
  });
  return image;
}

}  // namespace lhr
