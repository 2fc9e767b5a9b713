#include <filesystem>
#include <iostream>
#include <string>

#include "apps/commands.hpp"
#include "apps/options.hpp"
#include "io/output_dir.hpp"
#include "io/paper_scenes.hpp"
#include "io/scene_writer.hpp"

namespace lhr::app {

int run_scene(const Args& args) {
  std::string names;
  for (const std::string& n : paper_scene_names()) names += (names.empty() ? "" : ", ") + n;
  po::options_description visible("options");
  visible.add_options()("help,h", "show this help")
      ("out-dir,o", po::value<std::string>()->default_value("."), "directory for NAME.obj, NAME.mtl, NAME.scene.json")
      ("list", "print the names of the scenes");
  po::variables_map vm;
  const std::string usage = "usage: lhr scene NAME [--out-dir DIR]\n\n"
                            "Writes one of the paper's test scenes (§6) as OBJ/MTL plus a scene JSON\n"
                            "with its camera. Scenes: " + names + ".";
  if (!parse_command_line(args, usage.c_str(), visible, Positional{"name", false}, vm)) return kExitOk;
  if (vm.count("list")) {
    for (const std::string& n : paper_scene_names()) std::cout << n << "\n";
    return kExitOk;
  }
  if (!vm.count("name")) throw po::error("missing scene NAME (one of: " + names + ")");
  const std::string name = vm["name"].as<std::string>();
  const PaperScene scene = make_paper_scene(name);
  // Created as `lhr solve` creates its --out.
  const std::filesystem::path out_dir = vm["out-dir"].as<std::string>();
  prepare_output_directory(out_dir);
  write_scene_files(scene, out_dir, name);
  std::cerr << "lhr scene: wrote " << name << ".obj, " << name << ".mtl, " << name << ".scene.json ("
            << scene.soup.faces.size() << " faces)\n";
  return kExitOk;
}

}  // namespace lhr::app
