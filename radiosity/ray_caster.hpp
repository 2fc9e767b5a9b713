#pragma once
// All visibility goes through one Embree scene over every surface triangle
// (docs/design.md §2, radiosity/): shadow rays for transport coefficients and the
// oracles, primary rays for images.

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "mesh/types.hpp"

struct RTCDeviceTy;
struct RTCSceneTy;

namespace lhr {

struct RayHit {
  int surface = -1;  // index into the meshes the scene was built from
  int face = -1;     // face index in that mesh
  double distance = 0.0;
  double u = 0.0, v = 0.0;  // barycentrics of corners 1 and 2 of the face
};

struct ShadowRay {
  Vec3 from;
  Vec3 to;
};

// How a batch of shadow rays is handed to Embree (they give identical
// answers; BENCHMARKS.md compares their speed).
enum class ShadowQuery {
  kSingle,    // one rtcOccluded1 per ray
  kStream,    // rtcOccluded1M over the batch
  kPacket4,   // rtcOccluded4 per 4 rays
  kPacket8,   // rtcOccluded8 per 8 rays
  kPacket16,  // rtcOccluded16 per 16 rays
};

class RayCaster {
 public:
  // One Embree geometry per surface mesh (geometry id = surface index).
  // Built in robust mode: rays grazing shared edges must not leak.
  explicit RayCaster(const std::vector<const TriMesh*>& surfaces);
  ~RayCaster();
  RayCaster(const RayCaster&) = delete;
  RayCaster& operator=(const RayCaster&) = delete;

  // Offset that lifts ray end points off their surfaces: large enough for
  // Embree's single-precision hits at the scene's coordinates, small against
  // its features.
  double epsilon() const { return epsilon_; }
  double diagonal() const { return diagonal_; }

  // Whether anything blocks the open segment (from, to), stopped epsilon()
  // short of `to`. Lift the end points off their surfaces first (lift()).
  bool occluded(const Vec3& from, const Vec3& to) const;
  // Many segments at once, the fastest way measured; blocked[i] = 1 if occluded.
  void occluded(std::span<const ShadowRay> rays, std::span<std::uint8_t> blocked) const;
  // The same with a chosen Embree query.
  void occluded(std::span<const ShadowRay> rays, std::span<std::uint8_t> blocked, ShadowQuery query) const;

  // A point lifted off its surface along the unit normal n by epsilon().
  Vec3 lift(const Vec3& p, const Vec3& n) const { return p + epsilon_ * n; }

  std::optional<RayHit> intersect(const Vec3& origin, const Vec3& direction) const;

 private:
  RTCDeviceTy* device_ = nullptr;
  RTCSceneTy* scene_ = nullptr;
  double epsilon_ = 0.0;
  double diagonal_ = 0.0;
};

}  // namespace lhr
