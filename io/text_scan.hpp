#pragma once
// Text scanning shared by the loaders (io/ internal): files split into
// tokens with line numbers, numbers parsed strictly and faces checked, so
// that every problem becomes an InputError naming file and line (docs/design.md §3).

#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "io/input_error.hpp"
#include "mesh/types.hpp"

namespace lhr::text {

// s with line breaks and tabs turned into spaces, trailing spaces removed.
std::string one_line(std::string s);
std::string lower(std::string s);
// Lower-case extension with its dot (".obj").
std::string extension_of(const std::filesystem::path& path);
// s quoted for a message, cut to 40 characters.
std::string show(std::string_view s);

// The whole file; checkpoint, when set, is called between slices of a few
// megabytes, so that a caller can stop a long read.
std::string read_file(const std::filesystem::path& path, const std::function<void()>& checkpoint = {});
// Lines or elements a reader parses between two calls of its checkpoint: a
// few milliseconds of work.
inline constexpr long long kItemsPerCheckpoint = 4096;
// text without a leading UTF-8 byte-order mark: Windows editors write one,
// and it would glue itself to the first keyword of an OBJ or MTL.
std::string without_bom(std::string text);

// Text formats never contain NUL or most other control bytes; finding one
// means binary data (a wrong or corrupt file), which the parsers would
// otherwise skip silently.
// checkpoint as for read_file.
void require_text(const std::filesystem::path& path, std::string_view text,
                  const std::function<void()>& checkpoint = {});

struct Line {
  int number = 0;
  std::vector<std::string_view> tokens;  // never empty
};

// Splits text into whitespace-separated tokens per line, dropping blank
// lines; '#' starts a comment when strip_comments is set.
std::vector<Line> tokenize(std::string_view text, bool strip_comments);

// The lines tokenize returns, one at a time: a large file is read without
// holding every line's tokens at once, and its reader can stop between lines.
class LineReader {
 public:
  LineReader(std::string_view text, bool strip_comments) : text_(text), strip_comments_(strip_comments) {}
  // The next line with tokens, false after the last.
  bool next(Line& line);

 private:
  std::string_view text_;
  bool strip_comments_;
  std::size_t pos_ = 0;
  int number_ = 0;
  bool done_ = false;
};

// The whole token as a number, or nothing.
std::optional<double> parse_double(std::string_view token);
std::optional<long long> parse_int(std::string_view token);

// The three finite numbers at line.tokens[first ...].
Vec3 finite_xyz(const std::filesystem::path& path, const Line& line, std::size_t first, const std::string& what);

using ErrorAt = std::function<InputError(const std::string& problem)>;

// Indices must be in range and a face must span >= 3 distinct vertices.
// Repeats of a neighbouring vertex (common in exports) are removed; any
// other repeat makes the polygon self-touching, which no mesher accepts.
std::vector<int> checked_face(const std::vector<long long>& indices, long long n_vertices, const ErrorAt& error);

}  // namespace lhr::text
