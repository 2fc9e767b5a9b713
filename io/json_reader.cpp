#include "io/json_reader.hpp"

#include <cmath>

namespace lhr {

const JsonReader::Json& JsonReader::member(const Json& object, const std::string& key,
                                           const std::string& where) const {
  if (!object.contains(key)) fail("missing key \"" + where + key + "\"");
  return object.at(key);
}

double JsonReader::number(const Json& value, const std::string& name) const {
  if (!value.is_number()) fail("\"" + name + "\" must be a number");
  const double v = value.get<double>();
  if (!std::isfinite(v)) fail("\"" + name + "\" must be finite");
  return v;
}

Vec3 JsonReader::vec3(const Json& value, const std::string& name) const {
  if (!value.is_array() || value.size() != 3) fail("\"" + name + "\" must be an array of three numbers");
  Vec3 v;
  for (int k = 0; k < 3; ++k) v[k] = number(value[k], name + "[" + std::to_string(k) + "]");
  return v;
}

int JsonReader::positive_int(const Json& value, const std::string& name) const {
  if (!value.is_number_integer() || value.get<long long>() <= 0 || value.get<long long>() > (1 << 16)) {
    fail("\"" + name + "\" must be a positive integer (at most 65536)");
  }
  return value.get<int>();
}

Rgb JsonReader::colour(const Json& value, const std::string& name) const {
  if (value.is_number()) {
    const double grey = number(value, name);
    return Rgb(grey, grey, grey);
  }
  if (!value.is_array() || value.size() != 3) fail("\"" + name + "\" must be three numbers [r, g, b] or one number");
  Rgb c;
  for (int k = 0; k < 3; ++k) c[k] = number(value[k], name + "[" + std::to_string(k) + "]");
  return c;
}

}  // namespace lhr
