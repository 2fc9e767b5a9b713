#include "io/scene_generator.hpp"
#include <stdexcept>
namespace lhr {
std::vector<std::string> generated_scene_names() { return {"two-rooms", "four-rooms"}; }
GeneratedScene generate_scene(const std::string&) { throw std::logic_error("not implemented"); }
void write_scene_files(const GeneratedScene&, const std::filesystem::path&, const std::string&) { throw std::logic_error("not implemented"); }
}  // namespace lhr
