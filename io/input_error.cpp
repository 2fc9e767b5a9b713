#include "io/input_error.hpp"

namespace lhr {

InputError::InputError(const std::filesystem::path& file, int line, const std::string& problem)
    : std::runtime_error(file.string() + ":" + std::to_string(line) + ": " + problem) {}

InputError::InputError(const std::filesystem::path& file, const std::string& problem)
    : std::runtime_error(file.string() + ": " + problem) {}

}  // namespace lhr
