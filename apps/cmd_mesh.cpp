#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <string>
#include <unistd.h>

#include "apps/commands.hpp"
#include "apps/interrupt.hpp"
#include "apps/options.hpp"
#include "io/output_dir.hpp"
#include "io/mesh_io.hpp"
#include "io/scene_loader.hpp"
#include "mesh/initial_mesh.hpp"

namespace lhr::app {

namespace {

std::uint8_t to_byte(double v) {
  return static_cast<std::uint8_t>(std::lround(255.0 * std::clamp(v, 0.0, 1.0)));
}

// Loads, meshes and writes; throws Interrupted at the next surface, or
// before the mesh replaces an earlier file, after a signal.
int mesh_scene(const po::variables_map& vm, const std::filesystem::path& out_path, bool quiet) {
  LoadResult loaded = load_scene(vm["scene"].as<std::string>(), load_options_from(vm));
  if (!quiet) {
    for (const std::string& w : loaded.warnings) std::cerr << "lhr mesh: warning: " << w << "\n";
  }
  const Scene& scene = loaded.scene;

  const MeshingOptions meshing = meshing_options_from(vm, scene);

  const bool progress = !quiet && ::isatty(STDERR_FILENO);
  const double tolerance = contact_tolerance(scene.surfaces);
  const auto contacts = find_contact_lines(scene.surfaces, tolerance);
  ExportMesh out;
  for (std::size_t i = 0; i < scene.surfaces.size(); ++i) {
    throw_if_interrupted();
    const Surface& surface = scene.surfaces[i];
    if (progress) std::cerr << "\rmeshing surface " << (i + 1) << "/" << scene.surfaces.size() << std::flush;
    const TriMesh mesh = mesh_surface(surface, meshing, contacts[i], tolerance);
    const Material& material = scene.materials[surface.material];
    const std::size_t first = out.points.size();
    append_to_export(out, mesh, std::vector<Rgb>(mesh.n_vertices(), material.emission));
    out.colours.resize(out.points.size());
    for (std::size_t v = first; v < out.points.size(); ++v) {
      out.colours[v] = {to_byte(material.reflectance[0]), to_byte(material.reflectance[1]),
                        to_byte(material.reflectance[2])};
    }
  }
  out.colour_meaning = "the surface's reflectance Kd, 8 bit, linear";
  out.radiance_meaning = "the surface's emitted radiance Ke (the mesh is not lit)";
  if (progress) std::cerr << "\n";
  // Staged, then checked for a signal that came during the write: an
  // interrupted run leaves neither a temporary nor a new file.
  AtomicOutputs outputs;
  write_mesh(outputs, out_path, out);
  throw_if_interrupted();
  outputs.publish();
  if (!quiet) {
    std::cerr << "lhr mesh: " << scene.surfaces.size() << " surfaces, h = " << meshing.max_edge << ", "
              << out.points.size() << " vertices, " << out.triangles.size() << " triangles -> "
              << out_path.string() << "\n";
  }
  return kExitOk;
}

}  // namespace

int run_mesh(const Args& args) {
  po::options_description visible("options");
  visible.add_options()("help,h", "show this help")
      ("out,o", po::value<std::string>()->required(), "output mesh, .ply or .off")
      ("quiet,q", "print nothing but errors");
  add_scene_meshing_options(visible);
  po::variables_map vm;
  if (!parse_command_line(args,
                          "usage: lhr mesh SCENE --out FILE.ply|FILE.off [options]\n\n"
                          "Loads SCENE (.scene.json, .obj, .ply or .off), splits it into surfaces and\n"
                          "meshes each to the minimum density h (constrained Delaunay for planar surfaces,\n"
                          "isotropic remeshing for curved ones). The mesh is written with each surface's\n"
                          "reflectance as vertex colour and its emitted radiance as radiance.",
                          visible, Positional{"scene"}, vm)) {
    return kExitOk;
  }
  const bool quiet = vm.count("quiet") > 0;
  const std::filesystem::path out_path = vm["out"].as<std::string>();
  // Refuse an unusable output name or location before the work, not after.
  if (!is_mesh_output_format(out_path)) throw po::error("--out must name a .ply or .off file");
  check_output_file_location(out_path);
  install_interrupt_handlers();
  try {
    return mesh_scene(vm, out_path, quiet);
  } catch (const Interrupted& e) {
    if (!quiet && ::isatty(STDERR_FILENO)) std::cerr << "\n";
    std::cerr << "lhr mesh: " << e.what() << "\n";
    return kExitInterrupted;
  }
}

}  // namespace lhr::app
