#include "io/text_scan.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <set>
#include <utility>

namespace lhr::text {

namespace fs = std::filesystem;

std::string one_line(std::string s) {
  for (char& c : s) {
    if (c == '\n' || c == '\r' || c == '\t') c = ' ';
  }
  while (!s.empty() && s.back() == ' ') s.pop_back();
  return s;
}

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
  return s;
}

std::string extension_of(const fs::path& path) { return lower(path.extension().string()); }

std::string show(std::string_view s) {
  constexpr std::size_t kMax = 40;
  std::string q(s.substr(0, kMax));
  if (s.size() > kMax) q.append("...");
  // Built by appends: GCC 12 under ASan reports a false -Wrestrict for "'" + q.
  std::string quoted(1, '\'');
  quoted.append(one_line(std::move(q)));
  quoted.push_back('\'');
  return quoted;
}

std::string read_file(const fs::path& path, const std::function<void()>& checkpoint) {
  std::error_code ec;
  if (!fs::exists(path, ec)) throw InputError(path, "file not found");
  if (fs::is_directory(path, ec)) throw InputError(path, "is a directory, not a file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, "cannot open file for reading");
  // Read in slices into one buffer sized from the file: a file of tens of
  // megabytes takes a tenth of a second or more to read, and a signal must
  // not wait for that (docs/robustness.md, "Interrupted runs").
  constexpr std::size_t kSlice = std::size_t{1} << 22;
  const std::uintmax_t size = fs::file_size(path, ec);
  std::string text;
  if (!ec) text.reserve(static_cast<std::size_t>(size) + kSlice);
  while (in) {
    if (checkpoint) checkpoint();
    const std::size_t had = text.size();
    text.resize(had + kSlice);
    in.read(text.data() + had, static_cast<std::streamsize>(kSlice));
    text.resize(had + static_cast<std::size_t>(in.gcount()));
  }
  if (in.bad()) throw InputError(path, "read error");
  return text;
}

std::string without_bom(std::string text) {
  if (text.rfind("\xEF\xBB\xBF", 0) == 0) text.erase(0, 3);
  return text;
}

void require_text(const fs::path& path, std::string_view text, const std::function<void()>& checkpoint) {
  constexpr std::size_t kSlice = std::size_t{1} << 22;
  int line = 1;
  for (std::size_t at = 0; at < text.size(); ++at) {
    if (checkpoint && at % kSlice == 0) checkpoint();
    const unsigned char c = text[at];
    if (c == '\n') {
      ++line;
    } else if (c < 32 && c != '\t' && c != '\r' && c != '\f' && c != '\v') {
      char hex[8];
      std::snprintf(hex, sizeof hex, "0x%02x", c);
      throw InputError(path, line,
                       std::string("binary data (byte ") + hex + ") in a text file; is this the right file?");
    }
  }
}

bool LineReader::next(Line& line) {
  while (!done_) {
    std::size_t end = text_.find('\n', pos_);
    if (end == std::string_view::npos) end = text_.size();
    std::string_view raw = text_.substr(pos_, end - pos_);
    ++number_;
    if (end == text_.size()) {
      done_ = true;
    } else {
      pos_ = end + 1;
    }
    if (strip_comments_) {
      const std::size_t hash = raw.find('#');
      if (hash != std::string_view::npos) raw = raw.substr(0, hash);
    }
    line.number = number_;
    line.tokens.clear();
    std::size_t i = 0;
    while (i < raw.size()) {
      while (i < raw.size() && std::isspace(static_cast<unsigned char>(raw[i]))) ++i;
      std::size_t j = i;
      while (j < raw.size() && !std::isspace(static_cast<unsigned char>(raw[j]))) ++j;
      if (j > i) line.tokens.push_back(raw.substr(i, j - i));
      i = j;
    }
    if (!line.tokens.empty()) return true;
  }
  return false;
}

std::vector<Line> tokenize(std::string_view text, bool strip_comments) {
  std::vector<Line> lines;
  LineReader reader(text, strip_comments);
  Line line;
  while (reader.next(line)) lines.push_back(std::move(line));  // next() clears what is left
  return lines;
}

std::optional<double> parse_double(std::string_view token) {
  const std::string s(token);
  char* end = nullptr;
  const double v = std::strtod(s.c_str(), &end);
  if (s.empty() || end != s.c_str() + s.size()) return std::nullopt;
  return v;
}

std::optional<long long> parse_int(std::string_view token) {
  long long v = 0;
  const char* first = token.data();
  if (!token.empty() && token[0] == '+') ++first;
  const auto [ptr, ec] = std::from_chars(first, token.data() + token.size(), v);
  if (ec != std::errc() || ptr != token.data() + token.size() || first == token.data() + token.size()) {
    return std::nullopt;
  }
  return v;
}

Vec3 finite_xyz(const fs::path& path, const Line& line, std::size_t first, const std::string& what) {
  if (line.tokens.size() < first + 3) {
    throw InputError(path, line.number, what + " needs three coordinates x y z (truncated file?)");
  }
  Vec3 p;
  for (int k = 0; k < 3; ++k) {
    const std::string_view tok = line.tokens[first + k];
    const std::optional<double> v = parse_double(tok);
    if (!v) throw InputError(path, line.number, what + ": " + show(tok) + " is not a number");
    if (!std::isfinite(*v))
      throw InputError(path, line.number, what + ": non-finite coordinate " + show(tok));
    p[k] = *v;
  }
  return p;
}

std::vector<int> checked_face(const std::vector<long long>& indices, long long n_vertices,
                              const ErrorAt& error) {
  if (indices.size() < 3) {
    throw error("face has " + std::to_string(indices.size()) + " vertices (needs at least 3)");
  }
  for (long long i : indices) {
    if (i < 0 || i >= n_vertices) {
      throw error("face index " + std::to_string(i) + " out of range (" + std::to_string(n_vertices) +
                  " vertices)");
    }
  }
  std::vector<int> out;
  for (long long i : indices) {
    if (out.empty() || out.back() != i) out.push_back(static_cast<int>(i));
  }
  while (out.size() > 1 && out.front() == out.back()) out.pop_back();
  std::set<int> distinct(out.begin(), out.end());
  if (distinct.size() < 3) {
    throw error("face has " + std::to_string(distinct.size()) + " distinct vertices (needs at least 3)");
  }
  if (distinct.size() != out.size()) throw error("face visits the same vertex twice");
  return out;
}

}  // namespace lhr::text
