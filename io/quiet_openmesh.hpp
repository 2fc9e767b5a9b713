#pragma once
// OpenMesh's writers report through its own global streams and, in places,
// straight to std::cerr; lhr reports through one-line exceptions, so all of
// it is muted while a writer runs (io/ internal).

#include <sstream>

namespace lhr {

class QuietOpenMesh {
 public:
  QuietOpenMesh();
  ~QuietOpenMesh();
  QuietOpenMesh(const QuietOpenMesh&) = delete;
  QuietOpenMesh& operator=(const QuietOpenMesh&) = delete;

 private:
  std::stringbuf sink_;
  bool err_, log_, out_;
  std::streambuf* cerr_;
  std::streambuf* clog_;
};

}  // namespace lhr
