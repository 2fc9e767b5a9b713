#include "io/openmesh_import.hpp"

#include <OpenMesh/Core/System/omstream.hh>

#include <iostream>

namespace lhr {

QuietOpenMesh::QuietOpenMesh()
    : err_(omerr().is_enabled()),
      log_(omlog().is_enabled()),
      out_(omout().is_enabled()),
      cerr_(std::cerr.rdbuf(&sink_)),
      clog_(std::clog.rdbuf(&sink_)) {
  omerr().disable();
  omlog().disable();
  omout().disable();
}

QuietOpenMesh::~QuietOpenMesh() {
  std::cerr.rdbuf(cerr_);
  std::clog.rdbuf(clog_);
  if (err_) omerr().enable();
  if (log_) omlog().enable();
  if (out_) omout().enable();
}

OpenMesh::VertexHandle PlainImporter::add_vertex(const OpenMesh::Vec3d& p) {
  points.push_back(p);
  vertex_colours.emplace_back();
  return properties_.new_vertex();
}

OpenMesh::FaceHandle PlainImporter::add_face(const VHandles& indices) {
  if (indices.empty()) ++empty_faces;
  std::vector<int>& face = faces.emplace_back();
  face.reserve(indices.size());
  for (const auto& vh : indices) face.push_back(vh.idx());
  face_colours.emplace_back();
  return properties_.new_face();
}

void PlainImporter::set_point(OpenMesh::VertexHandle v, const OpenMesh::Vec3f& p) {
  if (v.idx() >= 0 && static_cast<std::size_t>(v.idx()) < points.size()) points[v.idx()] = OpenMesh::Vec3d(p);
}

void PlainImporter::reserve(unsigned int n_vertices, unsigned int /*n_edges*/, unsigned int n_faces) {
  declared_vertices = n_vertices;
  declared_faces = n_faces;
  // A corrupt header would have the reader loop over billions of empty records.
  if (std::uintmax_t{n_vertices} + n_faces > max_elements_) {
    throw ImportAborted{"header declares " + std::to_string(n_vertices) + " vertices and " +
                        std::to_string(n_faces) + " faces, more than a file of " + std::to_string(max_elements_) +
                        " bytes can hold"};
  }
  points.reserve(n_vertices);
  faces.reserve(n_faces);
}

}  // namespace lhr
