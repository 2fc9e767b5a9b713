#pragma once

#include <filesystem>
#include <stdexcept>
#include <string>

namespace lhr {

// Bad input a user can fix. what() is one line: "FILE:LINE: problem" (or
// "FILE: problem" when no line applies).
class InputError : public std::runtime_error {
 public:
  InputError(const std::filesystem::path& file, int line, const std::string& problem);
  InputError(const std::filesystem::path& file, const std::string& problem);
};

}  // namespace lhr
