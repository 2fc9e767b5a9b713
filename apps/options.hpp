#pragma once
// Shared Boost.Program_options plumbing for subcommands.

#include <boost/program_options.hpp>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <iostream>
#include <limits>
#include <stdexcept>
#include <string>

#include "apps/commands.hpp"
#include "apps/interrupt.hpp"
#include "io/scene_loader.hpp"
#include "mesh/initial_mesh.hpp"
#include "render/solution.hpp"

namespace lhr::app {

namespace po = boost::program_options;

using Clock = std::chrono::steady_clock;
inline double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

// The shortest text that reads back as v ("2.2", "1e-06"): Boost prints a
// default through a stream at full precision (2.2000000000000002).
inline std::string readable(double v) {
  char text[32];
  const auto end = std::to_chars(text, text + sizeof text, v).ptr;
  return std::string(text, end);
}

// A double option whose default --help shows as it was written.
inline po::typed_value<double>* double_value(double v) { return po::value<double>()->default_value(v, readable(v)); }

// How a command takes its one positional argument (SCENE, FILE, NAME).
struct Positional {
  const char* name;
  bool required = true;
};

// Parses args against the visible options plus the command's positional
// argument; prints help and returns false when --help was given.
inline bool parse_command_line(const Args& args, const std::string& usage, const po::options_description& visible,
                               const Positional& positional_arg, po::variables_map& vm) {
  po::options_description all;
  all.add(visible);
  auto* value = po::value<std::string>();
  if (positional_arg.required) value->required();
  all.add_options()(positional_arg.name, value, positional_arg.name);
  po::positional_options_description positional;
  positional.add(positional_arg.name, 1);
  po::store(po::command_line_parser(args).options(all).positional(positional).run(), vm);
  if (vm.count("help")) {
    std::cout << usage << "\n\n" << visible << "\n";
    return false;
  }
  po::notify(vm);
  return true;
}

// Options that load a scene and mesh it, shared by every command that does.
inline void add_scene_meshing_options(po::options_description& options) {
  options.add_options()
      ("max-edge", po::value<double>(),
       "h: longest edge of the initial mesh, in scene units (default: the scene file's, else 1/20 of "
       "the bounding-box diagonal)")
      ("min-angle", double_value(MeshingOptions{}.min_angle_deg),
       "smallest angle in degrees the mesher guarantees where the input boundary allows it")
      ("crease-angle", po::value<double>(),
       "degrees between face normals above which an edge separates two surfaces (default 30)");
}

inline LoadOptions load_options_from(const po::variables_map& vm) {
  LoadOptions options;
  if (vm.count("crease-angle")) options.crease_angle_deg = vm["crease-angle"].as<double>();
  options.checkpoint = throw_if_interrupted;
  return options;
}

// Flags override the scene file, which overrides the default h.
inline MeshingOptions meshing_options_from(const po::variables_map& vm, const Scene& scene) {
  MeshingOptions meshing;
  meshing.max_edge = vm.count("max-edge") ? vm["max-edge"].as<double>()
                                          : scene.settings.max_edge.value_or(default_max_edge(scene));
  meshing.min_angle_deg = vm["min-angle"].as<double>();
  meshing.checkpoint = throw_if_interrupted;
  try {
    check_meshing_options(meshing, OptionStyle::kFlag);
  } catch (const std::invalid_argument& e) {
    throw po::error(e.what());
  }
  return meshing;
}

// A size in bytes from "0", "1048576", "512K", "800M" or "2G" (powers of
// 1024); option names the flag in the error.
inline std::size_t parse_byte_size(const std::string& text, const std::string& option) {
  std::size_t used = 0;
  double value = -1.0;
  try {
    value = std::stod(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  double unit = 1.0;
  const std::string suffix = text.substr(used);
  if (suffix == "K" || suffix == "k") unit = 1024.0;
  if (suffix == "M" || suffix == "m") unit = 1024.0 * 1024.0;
  if (suffix == "G" || suffix == "g") unit = 1024.0 * 1024.0 * 1024.0;
  const bool suffix_ok = suffix.empty() || unit > 1.0;
  const double bytes = value * unit;
  if (used == 0 || !suffix_ok || !(bytes >= 0.0) ||
      bytes > static_cast<double>(std::numeric_limits<std::size_t>::max() / 2)) {
    throw po::error(option + " must be a size such as 512M or 2G, not '" + text + "'");
  }
  return static_cast<std::size_t>(bytes);
}

}  // namespace lhr::app
