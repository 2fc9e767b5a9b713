#include "io/json_file.hpp"

namespace lhr {

void write_json_file(const std::filesystem::path& path, const nlohmann::json& document) {
  AtomicOutputs outputs;
  write_json_file(outputs, path, document);
  outputs.publish();
}

void write_json_file(AtomicOutputs& outputs, const std::filesystem::path& path, const nlohmann::json& document) {
  outputs.stage(path, [&](std::ostream& out) { out << document.dump(2) << "\n"; });
}

}  // namespace lhr
