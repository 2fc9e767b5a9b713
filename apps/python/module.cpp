// The Python module lhr (README "Use lhr from Python"): what `lhr solve` and
// `lhr validate` do, with numpy arrays and dicts instead of files. Like the
// commands it only turns arguments into library calls.

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <array>
#include <chrono>
#include <cstdint>
#include <exception>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include <tbb/global_control.h>

#include "io/input_error.hpp"
#include "io/mesh_io.hpp"
#include "io/scene_loader.hpp"
#include "mesh/initial_mesh.hpp"
#include "mesh/validate.hpp"
#include "radiosity/memory_budget.hpp"
#include "render/solution.hpp"

namespace py = pybind11;

namespace lhr::python {

namespace {

// A Python signal handler raised while the solve ran. Its exception is
// already Python's error indicator on the calling thread; the translator
// leaves it there so that Ctrl-C arrives as KeyboardInterrupt.
struct SignalRaised : std::exception {
  const char* what() const noexcept override { return "interrupted by a signal"; }
};

// n rows of 3 copied from anything indexable twice: results own their data,
// so they outlive the C++ objects they come from.
template <class T, class Row>
py::array_t<T> rows_of_three(const std::vector<Row>& rows) {
  py::array_t<T> out({static_cast<py::ssize_t>(rows.size()), py::ssize_t{3}});
  auto view = out.template mutable_unchecked<2>();
  for (py::ssize_t i = 0; i < view.shape(0); ++i) {
    for (py::ssize_t j = 0; j < 3; ++j) view(i, j) = static_cast<T>(rows[static_cast<std::size_t>(i)][j]);
  }
  return out;
}

py::object triple(const Vec3& v) { return py::cast(std::array<double, 3>{v[0], v[1], v[2]}); }
py::object triple(const Rgb& c) { return py::cast(std::array<double, 3>{c[0], c[1], c[2]}); }

// Through text: stats.json is what `lhr solve` writes, so the dict matches
// json.load of that file key for key.
py::object to_python(const nlohmann::json& doc) { return py::module_::import("json").attr("loads")(doc.dump()); }

py::dict camera_dict(const Camera& camera) {
  py::dict d;
  d["eye"] = triple(camera.eye);
  d["target"] = triple(camera.target);
  d["up"] = triple(camera.up);
  d["fov_y_deg"] = camera.fov_y_deg;
  d["width"] = camera.width;
  d["height"] = camera.height;
  return d;
}

struct SolutionArrays {
  py::array vertices_;
  py::array faces_;
  py::array radiance_;
  py::array colors_;
  py::object stats_;
  std::vector<std::string> warnings_;
};

struct LoadedScene {
  std::string source_;
  py::array vertices_;
  std::vector<std::vector<int>> faces_;
  py::array face_surface_;
  py::array face_material_;
  py::list surfaces_;
  py::list materials_;
  py::object camera_;
  py::dict settings_;
  std::vector<std::string> warnings_;
  int dropped_zero_area_faces_ = 0;
};

struct StoredMesh {
  py::array vertices_;
  std::vector<std::vector<int>> faces_;
  py::object radiance_;
};

// Keyword arguments of solve() that override a default; None keeps it.
using Maybe = std::optional<double>;
using MaybeInt = std::optional<int>;

SolutionArrays solve(const std::filesystem::path& path, const std::string& method, Maybe eps_pixel, Maybe eps_link,
               Maybe eps_vertex, Maybe eps_power, Maybe vis_threshold, Maybe link_power, Maybe eps_bf, Maybe min_edge,
               MaybeInt max_iterations, Maybe tolerance, std::size_t max_links, std::optional<std::size_t> max_memory,
               MaybeInt visibility_samples, Maybe max_edge, Maybe min_angle, Maybe crease_angle,
               std::optional<std::string> tone_map, Maybe adaptation, Maybe units_to_cd, Maybe white,
               Maybe display_max, Maybe max_contrast, Maybe gamma, int threads) {
  const auto t_start = std::chrono::steady_clock::now();
  if (method != "linear" && method != "classical") {
    throw std::invalid_argument("method must be linear or classical, not '" + method + "'");
  }
  if (threads < 0) throw std::invalid_argument("threads must be 0 (all cores) or positive");
  SolveSettings settings;
  settings.method = method == "linear" ? SolveMethod::kLinear : SolveMethod::kClassical;
  LinearOptions& linear = settings.linear;
  ClassicalOptions& classical = settings.classical;
  if (eps_pixel) linear.eps_pixel = *eps_pixel;
  if (eps_link) linear.eps_link = *eps_link;
  if (eps_vertex) linear.eps_vertex = *eps_vertex;
  if (eps_power) linear.eps_power = *eps_power;
  if (vis_threshold) linear.vis_threshold = *vis_threshold;
  if (link_power) linear.link_power = *link_power;
  if (eps_bf) classical.eps_bf = *eps_bf;
  // Unset, each method keeps its own default, as `lhr solve` does.
  if (min_edge) linear.min_edge = classical.min_edge = *min_edge;
  if (max_iterations) linear.max_iterations = classical.max_iterations = *max_iterations;
  if (tolerance) linear.tolerance = classical.tolerance = *tolerance;
  if (visibility_samples) linear.visibility_samples = classical.visibility_samples = *visibility_samples;
  linear.max_links = classical.max_links = max_links;
  // None: the default budget of `lhr solve` (--max-memory auto); 0: no limit.
  linear.max_bytes = classical.max_bytes = max_memory.value_or(default_memory_budget());
  // Before the scene is read, as `lhr solve` checks its flags.
  check_solver_options(settings, OptionStyle::kKeyword);

  // Signals reach Python only on the thread that released the GIL; the
  // solver calls back from that thread between its phases.
  const std::thread::id caller = std::this_thread::get_id();
  const auto check_signals = [caller] {
    if (std::this_thread::get_id() != caller) return;
    py::gil_scoped_acquire gil;
    if (PyErr_CheckSignals() != 0) throw SignalRaised();
  };
  linear.checkpoint = classical.checkpoint = check_signals;

  LoadOptions load_options;
  load_options.crease_angle_deg = crease_angle;
  std::vector<std::string> warnings;
  lhr::Solution solution;
  {
    py::gil_scoped_release release;
    std::optional<tbb::global_control> thread_limit;
    if (threads > 0) {
      thread_limit.emplace(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
    }
    const LoadResult loaded = load_scene(path, load_options);
    warnings = loaded.warnings;
    const Scene& scene = loaded.scene;
    settings.camera = scene.camera.value_or(framing_camera(scene));
    check_image_budget(settings, OptionStyle::kKeyword);
    // Keywords override the scene file, which overrides the default h.
    settings.meshing.max_edge = max_edge.value_or(scene.settings.max_edge.value_or(default_max_edge(scene)));
    if (min_angle) settings.meshing.min_angle_deg = *min_angle;
    check_meshing_options(settings.meshing, OptionStyle::kKeyword);
    ToneMapSettings& tone = settings.tone;
    tone = scene.settings.tone_map;
    if (tone_map) tone.kind = tone_map_kind(*tone_map, OptionStyle::kKeyword);
    tone.world_adaptation = adaptation.value_or(tone.world_adaptation);
    tone.units_to_cd_m2 = units_to_cd.value_or(tone.units_to_cd_m2);
    tone.white = white.value_or(tone.white);
    tone.display_max_cd_m2 = display_max.value_or(tone.display_max_cd_m2);
    tone.max_contrast = max_contrast.value_or(tone.max_contrast);
    tone.gamma = gamma.value_or(tone.gamma);
    check_tone_settings(tone, OptionStyle::kKeyword);
    for (std::string& w : scene_warnings(scene)) warnings.push_back(std::move(w));
    solution = solve_scene(scene, settings, [&](int, double) { check_signals(); });
    for (std::string& w : solution_warnings(settings, solution, OptionStyle::kKeyword)) {
      warnings.push_back(std::move(w));
    }
  }

  const ExportMesh& mesh = solution.view.export_mesh;
  nlohmann::json doc = solution.stats;
  doc["lhr_version"] = LHR_VERSION;
  // No files are written, so there is no "output" phase; the process's peak
  // memory is the interpreter's, not the solve's, and is left out.
  doc["seconds"]["total"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
  SolutionArrays out;
  out.vertices_ = rows_of_three<double>(mesh.points);
  out.faces_ = rows_of_three<std::int64_t>(mesh.triangles);
  out.radiance_ = rows_of_three<double>(mesh.radiance);
  out.colors_ = rows_of_three<std::uint8_t>(mesh.colours);
  out.stats_ = to_python(doc);
  out.warnings_ = std::move(warnings);
  return out;
}

LoadedScene load(const std::filesystem::path& path, Maybe crease_angle) {
  LoadOptions options;
  options.crease_angle_deg = crease_angle;
  LoadResult loaded;
  {
    py::gil_scoped_release release;
    loaded = load_scene(path, options);
  }
  const Scene& scene = loaded.scene;
  LoadedScene out;
  out.source_ = scene.source;
  out.warnings_ = loaded.warnings;
  out.dropped_zero_area_faces_ = scene.dropped_zero_area_faces;
  std::vector<Vec3> points;
  std::vector<std::int64_t> face_surface, face_material;
  for (std::size_t s = 0; s < scene.surfaces.size(); ++s) {
    const Surface& surface = scene.surfaces[s];
    const int first = static_cast<int>(points.size());
    points.insert(points.end(), surface.points.begin(), surface.points.end());
    for (const std::vector<int>& polygon : surface.polygons) {
      std::vector<int> face;
      for (const int v : polygon) face.push_back(first + v);
      out.faces_.push_back(std::move(face));
      face_surface.push_back(static_cast<std::int64_t>(s));
      face_material.push_back(surface.material);
    }
    py::dict d;
    d["name"] = surface.name;
    d["material"] = surface.material;
    d["first_vertex"] = first;
    d["vertex_count"] = surface.points.size();
    d["planar"] = surface.planar;
    d["normal"] = triple(surface.normal);
    d["area"] = surface.area;
    out.surfaces_.append(d);
  }
  out.vertices_ = rows_of_three<double>(points);
  out.face_surface_ = py::array_t<std::int64_t>(static_cast<py::ssize_t>(face_surface.size()), face_surface.data());
  out.face_material_ =
      py::array_t<std::int64_t>(static_cast<py::ssize_t>(face_material.size()), face_material.data());
  for (const Material& m : scene.materials) {
    py::dict d;
    d["name"] = m.name;
    d["reflectance"] = triple(m.reflectance);
    d["emission"] = triple(m.emission);
    out.materials_.append(d);
  }
  out.camera_ = scene.camera ? py::object(camera_dict(*scene.camera)) : py::object(py::none());
  const ToneMapSettings& tone = scene.settings.tone_map;
  py::dict tone_map;
  tone_map["kind"] = tone_map_kind_name(tone.kind);
  tone_map["world_adaptation"] = tone.world_adaptation;
  tone_map["units_to_cd_m2"] = tone.units_to_cd_m2;
  tone_map["display_max_cd_m2"] = tone.display_max_cd_m2;
  tone_map["max_contrast"] = tone.max_contrast;
  tone_map["gamma"] = tone.gamma;
  tone_map["white"] = tone.white;
  out.settings_["max_edge"] = py::cast(scene.settings.max_edge);
  out.settings_["crease_angle_deg"] = py::cast(scene.settings.crease_angle_deg);
  out.settings_["tone_map"] = tone_map;
  return out;
}

std::vector<Violation> validate(const std::filesystem::path& path, double tolerance) {
  if (!(tolerance > 0)) throw std::invalid_argument("tolerance must be positive");
  py::gil_scoped_release release;
  const RawMesh mesh = read_raw_mesh(path);
  ConformingCheckOptions options;
  options.relative_tolerance = tolerance;
  return check_conforming_mesh(mesh, options);
}

StoredMesh read_mesh(const std::filesystem::path& path) {
  RawMesh mesh;
  {
    py::gil_scoped_release release;
    mesh = read_raw_mesh(path);
  }
  StoredMesh out;
  out.vertices_ = rows_of_three<double>(mesh.points);
  out.faces_ = std::move(mesh.faces);
  out.radiance_ = mesh.radiance.empty() ? py::object(py::none()) : py::object(rows_of_three<double>(mesh.radiance));
  return out;
}

}  // namespace

}  // namespace lhr::python

PYBIND11_MODULE(lhr, m) {
  using namespace lhr::python;
  namespace lp = lhr::python;
  m.doc() =
      "Linear hierarchical radiosity on triangle meshes: solve a scene (.scene.json, .obj, .ply, .off) and get "
      "the lit, refined mesh as numpy arrays, as `lhr solve` writes it to mesh.ply and stats.json.";
  m.attr("__version__") = LHR_VERSION;

  // Bad input a user can fix; the message is the library's one line, naming
  // the file and the line or element.
  py::register_exception<lhr::InputError>(m, "InputError", PyExc_ValueError);
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const SignalRaised&) {
      if (!PyErr_Occurred()) PyErr_SetString(PyExc_KeyboardInterrupt, "interrupted");
    }
  });

  py::class_<SolutionArrays>(m, "Solution", "The exported mesh of a solve and its statistics.")
      .def_readonly("vertices", &SolutionArrays::vertices_, "N x 3 float64: vertex positions, all surfaces in one mesh")
      .def_readonly("faces", &SolutionArrays::faces_, "M x 3 int64: triangles, counter-clockwise from the front")
      .def_readonly("radiance", &SolutionArrays::radiance_,
                    "N x 3 float64: linear radiance per vertex, in the units of the scene's emission Ke")
      .def_readonly("colors", &SolutionArrays::colors_,
                    "N x 3 uint8: display colour per vertex, tone-mapped and gamma-encoded (not linear)")
      .def_readonly("stats", &SolutionArrays::stats_,
                    "dict: what `lhr solve` writes to stats.json (without seconds.output and peak_memory_mib)")
      .def_readonly("warnings", &SolutionArrays::warnings_,
                    "list of str: what `lhr solve` prints as warnings (loading, budgets, convergence)")
      .def("__repr__", [](const SolutionArrays& s) {
        return "<lhr.Solution " + std::to_string(s.vertices_.shape(0)) + " vertices, " +
               std::to_string(s.faces_.shape(0)) + " triangles>";
      });

  py::class_<LoadedScene>(m, "Scene", "A scene as loaded: surfaces split at creases, before meshing.")
      .def_readonly("source", &LoadedScene::source_, "the file it was loaded from")
      .def_readonly("vertices", &LoadedScene::vertices_, "N x 3 float64: every surface's points, surface after surface")
      .def_readonly("faces", &LoadedScene::faces_,
                    "list of polygons, each a list of indices into vertices, counter-clockwise from the front")
      .def_readonly("face_surface", &LoadedScene::face_surface_, "int64 per face: its index into surfaces")
      .def_readonly("face_material", &LoadedScene::face_material_, "int64 per face: its index into materials")
      .def_readonly("surfaces", &LoadedScene::surfaces_,
                    "list of dict: name, material, first_vertex, vertex_count, planar, normal, area")
      .def_readonly("materials", &LoadedScene::materials_, "list of dict: name, reflectance (Kd), emission (Ke)")
      .def_readonly("camera", &LoadedScene::camera_,
                    "dict (eye, target, up, fov_y_deg, width, height): the file's camera, else one framing the "
                    "whole scene, as solve uses")
      .def_readonly("settings", &LoadedScene::settings_,
                    "dict: the file's max_edge and crease_angle_deg (None when absent), and tone_map with every "
                    "key (the defaults with the file's block over them)")
      .def_readonly("warnings", &LoadedScene::warnings_, "list of str: what was accepted but is worth knowing")
      .def_readonly("dropped_zero_area_faces", &LoadedScene::dropped_zero_area_faces_)
      .def("__repr__", [](const LoadedScene& s) {
        return "<lhr.Scene " + s.source_ + ": " + std::to_string(s.surfaces_.size()) + " surfaces, " +
               std::to_string(s.faces_.size()) + " faces>";
      });

  py::class_<StoredMesh>(m, "Mesh", "A PLY or OFF mesh exactly as the file stores it.")
      .def_readonly("vertices", &StoredMesh::vertices_, "N x 3 float64")
      .def_readonly("faces", &StoredMesh::faces_, "list of faces, each a list of vertex indices")
      .def_readonly("radiance", &StoredMesh::radiance_,
                    "N x 3 float64 when the file has radiance_r/g/b (lhr's mesh.ply), else None");

  py::class_<lhr::Violation>(m, "Violation", "One failed check of validate().")
      .def_readonly("kind", &lhr::Violation::kind, "short id: t-junction, orientation, non-manifold-edge, ...")
      .def_readonly("where", &lhr::Violation::where, "e.g. 'face 12', 'edge (3,7)', 'vertex 5'")
      .def_readonly("detail", &lhr::Violation::detail)
      .def("__str__", &lhr::format_violation)
      .def("__repr__", [](const lhr::Violation& v) { return "<lhr.Violation " + lhr::format_violation(v) + ">"; });

  const lhr::LinearOptions linear;
  const lhr::ClassicalOptions classical;
  m.def("solve", &lp::solve,
        "solve(path, method='linear', **options) -> Solution\n\n"
        "Computes diffuse global illumination for a scene file, as `lhr solve` does, and returns the lit, "
        "refined mesh it writes to mesh.ply. Keywords mirror the command's flags (eps_pixel for --eps-pixel, "
        "...); None keeps the default, or the scene file's value where it has one. The GIL is released while "
        "solving; Ctrl-C stops at the next safe point. Raises lhr.InputError (a ValueError) for a bad scene "
        "file and ValueError for a bad option.",
        py::arg("path"), py::kw_only(), py::arg("method") = "linear",
        py::arg("eps_pixel").none(true) = py::none(), py::arg("eps_link").none(true) = py::none(),
        py::arg("eps_vertex").none(true) = py::none(), py::arg("eps_power").none(true) = py::none(),
        py::arg("vis_threshold").none(true) = py::none(),
        py::arg("link_power").none(true) = py::none(), py::arg("eps_bf").none(true) = py::none(),
        py::arg("min_edge").none(true) = py::none(), py::arg("max_iterations").none(true) = py::none(),
        py::arg("tolerance").none(true) = py::none(), py::arg("max_links") = std::size_t{0},
        py::arg("max_memory").none(true) = py::none(), py::arg("visibility_samples").none(true) = py::none(),
        py::arg("max_edge").none(true) = py::none(), py::arg("min_angle").none(true) = py::none(),
        py::arg("crease_angle").none(true) = py::none(), py::arg("tone_map").none(true) = py::none(),
        py::arg("adaptation").none(true) = py::none(), py::arg("units_to_cd").none(true) = py::none(),
        py::arg("white").none(true) = py::none(), py::arg("display_max").none(true) = py::none(),
        py::arg("max_contrast").none(true) = py::none(), py::arg("gamma").none(true) = py::none(),
        py::arg("threads") = 0);
  m.attr("DEFAULTS") = py::dict(py::arg("eps_pixel") = linear.eps_pixel, py::arg("eps_link") = linear.eps_link,
                                py::arg("eps_vertex") = linear.eps_vertex, py::arg("eps_power") = linear.eps_power,
                                py::arg("vis_threshold") = linear.vis_threshold,
                                py::arg("link_power") = linear.link_power, py::arg("eps_bf") = classical.eps_bf);

  m.def("load_scene", &lp::load,
        "load_scene(path, crease_angle=None) -> Scene\n\n"
        "Reads a scene (.scene.json, .obj, .ply, .off) as `lhr solve` does before meshing. Raises "
        "lhr.InputError naming the file and line for bad input.",
        py::arg("path"), py::kw_only(), py::arg("crease_angle").none(true) = py::none());

  m.def("validate", &lp::validate,
        "validate(path, tolerance=1e-6) -> list of Violation\n\n"
        "The checks of `lhr validate FILE` on a PLY or OFF mesh as stored: indices in range, finite values, no "
        "degenerate or duplicated faces, manifold edges and vertices, consistent orientation, no T-junction "
        "cracks. Empty when all hold. tolerance is relative to the bounding-box diagonal.",
        py::arg("path"), py::kw_only(), py::arg("tolerance") = lhr::kStoredMeshTolerance);

  m.def("read_mesh", &lp::read_mesh,
        "read_mesh(path) -> Mesh\n\nA PLY or OFF mesh exactly as stored (no merging, no repair), e.g. the "
        "mesh.ply `lhr solve` writes.",
        py::arg("path"));
}
