#include "io/json_file.hpp"

#include <fstream>
#include <stdexcept>

#include "io/atomic_file.hpp"

namespace lhr {

void write_json_file(const std::filesystem::path& path, const nlohmann::json& document) {
  write_atomically(path, [&](const std::filesystem::path& temp) {
    std::ofstream out(temp);
    out << document.dump(2) << "\n";
    out.close();
    if (!out) throw std::runtime_error(path.string() + ": cannot write");
  });
}

}  // namespace lhr
