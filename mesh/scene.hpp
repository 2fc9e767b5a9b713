#pragma once
// The scene contract (docs/design.md §3) as plain values: what loaders produce and
// meshing, solvers and renderers consume.

#include <optional>
#include <utility>
#include <string>
#include <vector>

#include "mesh/tone_map_settings.hpp"
#include "mesh/types.hpp"

namespace lhr {

struct Material {
  std::string name;
  Rgb reflectance{0.5, 0.5, 0.5};  // Kd, each channel in [0,1)
  Rgb emission{0.0, 0.0, 0.0};     // Ke, emitted radiance
  bool is_emitter() const { return emission[0] > 0 || emission[1] > 0 || emission[2] > 0; }
};

// Pinhole camera; pixel (0,0) is top-left, one ray through each pixel centre.
struct Camera {
  Vec3 eye{0, 0, 1};
  Vec3 target{0, 0, 0};
  Vec3 up{0, 1, 0};
  double fov_y_deg = 45.0;  // over the full image height
  int width = 512;
  int height = 512;
};

// A face as loaded, before it is grouped into surfaces.
struct InputFace {
  std::vector<int> vertices;  // indices into PolygonSoup::points, counter-clockwise from the front
  int material = 0;           // index into PolygonSoup::materials
  int group = 0;              // index into PolygonSoup::groups (OBJ object/group)
  int source_line = 0;        // line (OBJ, OFF) or element index (PLY) for messages; 0 if unknown
};

struct PolygonSoup {
  std::vector<Vec3> points;
  std::vector<InputFace> faces;
  std::vector<Material> materials;
  std::vector<std::string> groups;
};

// The paper's "mesh": connected input faces with one material inside one
// group, cut along creases. Radiance is C0 inside a surface and may jump
// between surfaces, so each surface owns its vertices.
struct Surface {
  std::string name;
  int material = 0;
  std::vector<Vec3> points;
  std::vector<std::vector<int>> polygons;  // indices into points, counter-clockwise from the front
  bool planar = false;                     // all points within a relative tolerance of one plane
  Vec3 normal{0, 0, 0};                    // unit front normal (area-weighted mean)
  double area = 0.0;
  // Edges (pairs of indices into points) that the surface shares with a face
  // of another surface: a crease, a change of material or group, a
  // non-manifold edge. Every other boundary edge is open, and meshing a
  // curved surface may coarsen it (docs/design.md §4, "Curved surfaces").
  std::vector<std::pair<int, int>> seam_edges;
};

// Settings a scene file may carry; command-line flags override them.
struct SceneSettings {
  std::optional<double> max_edge;
  std::optional<double> crease_angle_deg;
  ToneMapSettings tone_map;  // the defaults with the file's "tone_map" block over them
};

struct Scene {
  std::string source;  // file the scene was loaded from, for messages
  std::vector<Material> materials;
  std::vector<Surface> surfaces;
  std::optional<Camera> camera;
  SceneSettings settings;
  int dropped_zero_area_faces = 0;
};

// Axis-aligned bounds of every surface point.
struct Bounds {
  Vec3 min{0, 0, 0};
  Vec3 max{0, 0, 0};
  double diagonal() const { return (max - min).norm(); }
};
Bounds scene_bounds(const Scene& scene);

// A camera that frames the whole scene, for bare OBJ/PLY/OFF input.
Camera framing_camera(const Scene& scene);

}  // namespace lhr
