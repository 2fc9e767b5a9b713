#pragma once
// Checked reads from a parsed scene file (io/ internal): every problem is an
// InputError naming the file and the key, so a user can find and fix it
// (docs/scene-format.md).

#include <filesystem>
#include <string>
#include <utility>

#include <nlohmann/json.hpp>

#include "io/input_error.hpp"
#include "mesh/types.hpp"

namespace lhr {

class JsonReader {
 public:
  using Json = nlohmann::json;

  explicit JsonReader(std::filesystem::path path) : path_(std::move(path)) {}

  const std::filesystem::path& path() const { return path_; }

  [[noreturn]] void fail(const std::string& problem) const { throw InputError(path_, problem); }

  const Json& member(const Json& object, const std::string& key, const std::string& where) const;
  double number(const Json& value, const std::string& name) const;
  Vec3 vec3(const Json& value, const std::string& name) const;
  int positive_int(const Json& value, const std::string& name) const;
  // Three numbers r g b, or one number for a grey.
  Rgb colour(const Json& value, const std::string& name) const;

 private:
  std::filesystem::path path_;
};

}  // namespace lhr
