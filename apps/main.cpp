// lhr: linear hierarchical radiosity with an image-space refinement criterion.

#include <boost/program_options/errors.hpp>
#include <exception>
#include <iostream>
#include <string>

#include "apps/commands.hpp"

namespace {

struct Command {
  const char* name;
  int (*run)(const lhr::app::Args&);
  const char* summary;
};

constexpr Command kCommands[] = {
    {"solve", lhr::app::run_solve, "compute the lit, refined mesh and a view of it"},
    {"mesh", lhr::app::run_mesh, "mesh a scene to a minimum density and write the initial mesh"},
    {"validate", lhr::app::run_validate, "check a PLY/OFF mesh: manifold, oriented, crack-free"},
    {"scene", lhr::app::run_scene, "write one of the paper's generated test scenes"},
    {"reference", lhr::app::run_reference, "path-trace a reference image (or a mesh's vertices) and report its noise"},
    {"compare", lhr::app::run_compare, "measure an image or mesh against a reference (the paper's 10 %/15 % norms)"},
    {"bench", lhr::app::run_bench, "chart image accuracy against links, time and memory for every method"},
};

void print_usage(std::ostream& out) {
  out << "usage: lhr <command> [options]\n\n"
         "Diffuse global illumination on triangle meshes by linear hierarchical\n"
         "radiosity with an image-space refinement criterion.\n\ncommands:\n";
  for (const Command& c : kCommands) {
    out << "  " << c.name << std::string(10 - std::string(c.name).size(), ' ') << c.summary << "\n";
  }
  out << "\n'lhr <command> --help' describes a command's options; 'lhr --version' prints the version.\n\n"
         "exit status: 0 done; 1 bad input, an invalid mesh (validate) or an I/O error, with one\n"
         "line naming the file and the problem; 2 a bad command line; 130 stopped by Ctrl-C or SIGTERM,\n"
         "earlier outputs left as they were.\n";
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    print_usage(std::cerr);
    return lhr::app::kExitUsage;
  }
  const std::string name = argv[1];
  if (name == "--version" || name == "-V") {
    std::cout << "lhr " << LHR_VERSION << "\n";
    return lhr::app::kExitOk;
  }
  if (name == "--help" || name == "-h" || name == "help") {
    print_usage(std::cout);
    return lhr::app::kExitOk;
  }
  for (const Command& c : kCommands) {
    if (name != c.name) continue;
    const lhr::app::Args args(argv + 2, argv + argc);
    try {
      return c.run(args);
    } catch (const boost::program_options::error& e) {
      std::cerr << "lhr " << name << ": " << e.what() << " (see 'lhr " << name << " --help')\n";
      return lhr::app::kExitUsage;
    } catch (const std::exception& e) {
      std::cerr << "lhr " << name << ": error: " << e.what() << "\n";
      return lhr::app::kExitFailure;
    }
  }
  std::cerr << "lhr: unknown command '" << name << "'\n\n";
  print_usage(std::cerr);
  return lhr::app::kExitUsage;
}
