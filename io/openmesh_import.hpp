#pragma once
// Reading PLY/OFF through OpenMesh's readers exactly as stored (io/ internal).
// OpenMesh's own importer builds half-edges, so it drops non-manifold faces
// and cannot hold out-of-range indices; the loaders and `lhr validate` must
// see the file as it is to report what is wrong with it.

#include <OpenMesh/Core/IO/importer/BaseImporter.hh>
#include <OpenMesh/Core/Mesh/ArrayKernel.hh>

#include <cstdint>
#include <limits>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "mesh/types.hpp"

namespace lhr {

// OpenMesh reports through its own global streams and, in places, straight
// to std::cerr; lhr reports through one-line exceptions, so all of it is
// muted while a reader runs.
class QuietOpenMesh {
 public:
  QuietOpenMesh();
  ~QuietOpenMesh();
  QuietOpenMesh(const QuietOpenMesh&) = delete;
  QuietOpenMesh& operator=(const QuietOpenMesh&) = delete;

 private:
  std::stringbuf sink_;
  bool err_, log_, out_;
  std::streambuf* cerr_;
  std::streambuf* clog_;
};

// Thrown from inside OpenMesh's reader to stop it early on a hopeless header.
struct ImportAborted {
  std::string problem;
};

// Records points, faces and colours as the reader delivers them. Custom PLY
// properties (radiance) land in properties(), indexed like the points.
class PlainImporter : public OpenMesh::IO::BaseImporter {
 public:
  // Headers declaring more elements than this (e.g. the file's size in
  // bytes: every element takes at least one) abort the read.
  explicit PlainImporter(std::uintmax_t max_elements = std::numeric_limits<std::uintmax_t>::max())
      : max_elements_(max_elements) {}

  std::vector<Vec3> points;
  std::vector<std::vector<int>> faces;
  std::vector<std::optional<Rgb>> vertex_colours;
  std::vector<std::optional<Rgb>> face_colours;
  std::size_t declared_vertices = 0;
  std::size_t declared_faces = 0;
  std::size_t empty_faces = 0;  // faces read with no index (a failed text parse)
  const OpenMesh::ArrayKernel& properties() const { return properties_; }

  OpenMesh::VertexHandle add_vertex(const OpenMesh::Vec3f& p) override { return add_vertex(OpenMesh::Vec3d(p)); }
  OpenMesh::VertexHandle add_vertex(const OpenMesh::Vec3d& p) override;
  OpenMesh::VertexHandle add_vertex() override { return add_vertex(OpenMesh::Vec3d(0.0)); }
  OpenMesh::FaceHandle add_face(const VHandles& indices) override;
  void set_point(OpenMesh::VertexHandle v, const OpenMesh::Vec3f& p) override;
  void set_color(OpenMesh::VertexHandle v, const OpenMesh::Vec3uc& c) override { set(vertex_colours, v.idx(), bytes(c)); }
  void set_color(OpenMesh::VertexHandle v, const OpenMesh::Vec4uc& c) override {
    set(vertex_colours, v.idx(), bytes(OpenMesh::Vec3uc(c[0], c[1], c[2])));
  }
  void set_color(OpenMesh::VertexHandle v, const OpenMesh::Vec3f& c) override { set(vertex_colours, v.idx(), Rgb(c)); }
  void set_color(OpenMesh::VertexHandle v, const OpenMesh::Vec4f& c) override {
    set(vertex_colours, v.idx(), Rgb(c[0], c[1], c[2]));
  }
  void set_color(OpenMesh::FaceHandle f, const OpenMesh::Vec3uc& c) override { set(face_colours, f.idx(), bytes(c)); }
  void set_color(OpenMesh::FaceHandle f, const OpenMesh::Vec4uc& c) override {
    set(face_colours, f.idx(), bytes(OpenMesh::Vec3uc(c[0], c[1], c[2])));
  }
  void set_color(OpenMesh::FaceHandle f, const OpenMesh::Vec3f& c) override { set(face_colours, f.idx(), Rgb(c)); }
  void set_color(OpenMesh::FaceHandle f, const OpenMesh::Vec4f& c) override {
    set(face_colours, f.idx(), Rgb(c[0], c[1], c[2]));
  }
  void reserve(unsigned int n_vertices, unsigned int n_edges, unsigned int n_faces) override;
  std::size_t n_vertices() const override { return points.size(); }
  std::size_t n_faces() const override { return faces.size(); }
  std::size_t n_edges() const override { return 0; }
  OpenMesh::BaseKernel* kernel() override { return &properties_; }

  // Everything else a reader may hand over is not kept.
  OpenMesh::HalfedgeHandle add_edge(OpenMesh::VertexHandle, OpenMesh::VertexHandle) override {
    return OpenMesh::HalfedgeHandle();
  }
  OpenMesh::FaceHandle add_face(OpenMesh::HalfedgeHandle) override { return OpenMesh::FaceHandle(); }
  void add_face_texcoords(OpenMesh::FaceHandle, OpenMesh::VertexHandle, const std::vector<OpenMesh::Vec2f>&) override {}
  void add_face_texcoords(OpenMesh::FaceHandle, OpenMesh::VertexHandle, const std::vector<OpenMesh::Vec3f>&) override {}
  void set_face_texindex(OpenMesh::FaceHandle, int) override {}
  void set_halfedge(OpenMesh::VertexHandle, OpenMesh::HalfedgeHandle) override {}
  void set_normal(OpenMesh::VertexHandle, const OpenMesh::Vec3f&) override {}
  void set_normal(OpenMesh::VertexHandle, const OpenMesh::Vec3d&) override {}
  void set_texcoord(OpenMesh::VertexHandle, const OpenMesh::Vec2f&) override {}
  void set_status(OpenMesh::VertexHandle, const OpenMesh::Attributes::StatusInfo&) override {}
  void set_next(OpenMesh::HalfedgeHandle, OpenMesh::HalfedgeHandle) override {}
  void set_face(OpenMesh::HalfedgeHandle, OpenMesh::FaceHandle) override {}
  void request_face_texcoords2D() override {}
  void set_texcoord(OpenMesh::HalfedgeHandle, const OpenMesh::Vec2f&) override {}
  void set_texcoord(OpenMesh::VertexHandle, const OpenMesh::Vec3f&) override {}
  void set_texcoord(OpenMesh::HalfedgeHandle, const OpenMesh::Vec3f&) override {}
  void set_status(OpenMesh::HalfedgeHandle, const OpenMesh::Attributes::StatusInfo&) override {}
  void set_color(OpenMesh::EdgeHandle, const OpenMesh::Vec3uc&) override {}
  void set_color(OpenMesh::EdgeHandle, const OpenMesh::Vec4uc&) override {}
  void set_color(OpenMesh::EdgeHandle, const OpenMesh::Vec3f&) override {}
  void set_color(OpenMesh::EdgeHandle, const OpenMesh::Vec4f&) override {}
  void set_status(OpenMesh::EdgeHandle, const OpenMesh::Attributes::StatusInfo&) override {}
  void set_normal(OpenMesh::FaceHandle, const OpenMesh::Vec3f&) override {}
  void set_normal(OpenMesh::FaceHandle, const OpenMesh::Vec3d&) override {}
  void set_status(OpenMesh::FaceHandle, const OpenMesh::Attributes::StatusInfo&) override {}
  void add_texture_information(int, std::string) override {}

 private:
  static Rgb bytes(const OpenMesh::Vec3uc& c) { return Rgb(c[0], c[1], c[2]) / 255.0; }
  static void set(std::vector<std::optional<Rgb>>& colours, int i, const Rgb& c) {
    if (i >= 0 && static_cast<std::size_t>(i) < colours.size()) colours[i] = c;
  }

  std::uintmax_t max_elements_;
  OpenMesh::ArrayKernel properties_;
};

}  // namespace lhr
