#include "io/input_error.hpp"

#include <cstdio>

namespace lhr {

namespace {

// what() must stay one line whatever the file name or the file's own text
// quoted in the problem holds (a JSON key may contain a line break): control
// characters are shown escaped.
std::string escape_control_characters(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (const char c : text) {
    const auto byte = static_cast<unsigned char>(c);
    if (c == '\n') {
      out += "\\n";
    } else if (c == '\r') {
      out += "\\r";
    } else if (c == '\t') {
      out += "\\t";
    } else if (byte < 0x20 || byte == 0x7f) {
      char hex[8];
      std::snprintf(hex, sizeof hex, "\\x%02x", byte);
      out += hex;
    } else {
      out += c;
    }
  }
  return out;
}

}  // namespace

InputError::InputError(const std::filesystem::path& file, int line, const std::string& problem)
    : std::runtime_error(escape_control_characters(file.string() + ":" + std::to_string(line) + ": " + problem)) {}

InputError::InputError(const std::filesystem::path& file, const std::string& problem)
    : std::runtime_error(escape_control_characters(file.string() + ": " + problem)) {}

}  // namespace lhr
