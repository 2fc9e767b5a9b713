#include <iostream>
#include <string>

#include "apps/commands.hpp"
#include "apps/options.hpp"
#include "io/mesh_io.hpp"
#include "mesh/validate.hpp"

namespace lhr::app {

int run_validate(const Args& args) {
  po::options_description visible("options");
  visible.add_options()("help,h", "show this help")
      ("tolerance", double_value(kStoredMeshTolerance),
       "distance, relative to the bounding-box diagonal, under which a vertex counts as lying on an edge "
       "and a face as flat (files hold float coordinates, so keep it well above 1e-7)")
      ("quiet,q", "print nothing when every check holds");
  po::variables_map vm;
  if (!parse_command_line(args,
                          "usage: lhr validate FILE.ply|FILE.off [options]\n\n"
                          "Checks a mesh as stored: indices in range, finite values, no degenerate or\n"
                          "duplicated faces, manifold edges and vertices, consistent orientation, and no\n"
                          "T-junction cracks inside a connected component. Exits 0 when all hold, 1 with\n"
                          "one line per violation otherwise.",
                          visible, Positional{"file"}, vm)) {
    return kExitOk;
  }
  const std::string file = vm["file"].as<std::string>();
  const RawMesh mesh = read_raw_mesh(file);
  ConformingCheckOptions options;
  options.relative_tolerance = vm["tolerance"].as<double>();
  const std::vector<Violation> violations = check_conforming_mesh(mesh, options);
  if (violations.empty()) {
    if (!vm.count("quiet")) {
      std::cout << file << ": ok (" << mesh.points.size() << " vertices, " << mesh.faces.size()
                << " faces)\n";
    }
    return kExitOk;
  }
  for (const Violation& v : violations) std::cout << file << ": " << format_violation(v) << "\n";
  std::cout << file << ": " << violations.size() << " violation(s)\n";
  return kExitFailure;
}

}  // namespace lhr::app
