#pragma once
// The caller's checkpoint (MeshingOptions::checkpoint), called from inside
// the meshing code, and what it threw carried out of it unchanged.

#include <cstdint>
#include <exception>
#include <functional>

namespace lhr {

// What the caller's checkpoint threw, carried past the meshing code's own
// `catch (const std::exception&)` (the contact-line fallback, the surface's
// name added to errors) and rethrown unchanged by mesh_surface.
struct CheckpointThrew {
  std::exception_ptr thrown;
};

// CGAL's remeshing has no hook of its own; it reads every vertex position
// through the point map (mesh/cgal_meshing.cpp), so the map calls the
// checkpoint every so many reads.
class MeshingCheckpoint {
 public:
  explicit MeshingCheckpoint(const std::function<void()>& checkpoint) : checkpoint_(checkpoint) {}
  void operator()() const {
    if (!checkpoint_) return;
    try {
      checkpoint_();
    } catch (...) {
      throw CheckpointThrew{std::current_exception()};
    }
  }
  void tick() {
    if (++reads_ % kReadsPerCheck == 0) (*this)();
  }

 private:
  static constexpr std::uint64_t kReadsPerCheck = 1 << 14;
  const std::function<void()>& checkpoint_;
  std::uint64_t reads_ = 0;
};

}  // namespace lhr
