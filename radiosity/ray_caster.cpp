#include "radiosity/ray_caster.hpp"

#include <embree3/rtcore.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace lhr {

namespace {

// Embree stores float coordinates: a hit is exact to about 1e-7 of the
// coordinates' magnitude, so lifts must exceed that with margin.
constexpr double kRelativeEpsilon = 1e-5;

void throw_on_error(RTCDevice device, const char* what) {
  const RTCError error = rtcGetDeviceError(device);
  if (error != RTC_ERROR_NONE) {
    throw std::runtime_error(std::string("Embree failed while ") + what + " (error " +
                             std::to_string(static_cast<int>(error)) + ")");
  }
}

// A shadow ray stops `end_gap` short of `to`. An end point lifted off its own
// surface can still lie within Embree's single precision of another: a sample
// on a wall next to the ceiling, 10⁻⁸ below it, reached from below at a
// grazing angle, rounds onto the ceiling's plane and was found blocked there
// (one ray of a link in the furnace cube: its corner vertex read 1.9963, not
// 2). Stopping a lift's length short moves the end off both. The gap is
// taken against the largest coordinate of the segment, not its length: at
// least end_gap and at most √3 times it, without a square root per ray.
RTCRay make_segment_ray(const Vec3& from, const Vec3& to, double end_gap) {
  RTCRay ray{};
  const Vec3 d = to - from;
  const double length = std::max({std::abs(d[0]), std::abs(d[1]), std::abs(d[2])});
  ray.org_x = static_cast<float>(from[0]);
  ray.org_y = static_cast<float>(from[1]);
  ray.org_z = static_cast<float>(from[2]);
  ray.dir_x = static_cast<float>(d[0]);
  ray.dir_y = static_cast<float>(d[1]);
  ray.dir_z = static_cast<float>(d[2]);
  ray.tnear = 0.0f;
  // The direction spans the segment.
  ray.tfar = length > end_gap ? static_cast<float>(1.0 - end_gap / length) : 0.0f;
  ray.mask = 0xFFFFFFFFu;
  ray.flags = 0;
  return ray;
}

void occluded_stream(RTCScene scene, std::span<const ShadowRay> rays, std::span<std::uint8_t> blocked,
                     double end_gap) {
  constexpr std::size_t kChunk = 256;
  RTCRay buffer[kChunk];
  for (std::size_t first = 0; first < rays.size(); first += kChunk) {
    const std::size_t count = std::min(kChunk, rays.size() - first);
    for (std::size_t i = 0; i < count; ++i) {
      buffer[i] = make_segment_ray(rays[first + i].from, rays[first + i].to, end_gap);
    }
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    context.flags = RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
    rtcOccluded1M(scene, &context, buffer, static_cast<unsigned>(count), sizeof(RTCRay));
    for (std::size_t i = 0; i < count; ++i) blocked[first + i] = buffer[i].tfar < 0.0f ? 1 : 0;
  }
}

// Embree's packet types and queries by width.
struct Packet4 {
  static constexpr std::size_t kWidth = 4;
  using Ray = RTCRay4;
  static void occluded(const int* valid, RTCScene s, RTCIntersectContext* c, Ray* r) { rtcOccluded4(valid, s, c, r); }
};
struct Packet8 {
  static constexpr std::size_t kWidth = 8;
  using Ray = RTCRay8;
  static void occluded(const int* valid, RTCScene s, RTCIntersectContext* c, Ray* r) { rtcOccluded8(valid, s, c, r); }
};
struct Packet16 {
  static constexpr std::size_t kWidth = 16;
  using Ray = RTCRay16;
  static void occluded(const int* valid, RTCScene s, RTCIntersectContext* c, Ray* r) { rtcOccluded16(valid, s, c, r); }
};

template <class P>
void occluded_packets(RTCScene scene, std::span<const ShadowRay> rays, std::span<std::uint8_t> blocked,
                      double end_gap) {
  constexpr std::size_t kWidth = P::kWidth;
  // Embree wants the valid mask aligned like the packet.
  alignas(4 * kWidth) int valid[kWidth];
  typename P::Ray packet;
  for (std::size_t first = 0; first < rays.size(); first += kWidth) {
    const std::size_t count = std::min(kWidth, rays.size() - first);
    for (std::size_t i = 0; i < kWidth; ++i) {
      valid[i] = i < count ? -1 : 0;
      const RTCRay ray = i < count ? make_segment_ray(rays[first + i].from, rays[first + i].to, end_gap) : RTCRay{};
      packet.org_x[i] = ray.org_x;
      packet.org_y[i] = ray.org_y;
      packet.org_z[i] = ray.org_z;
      packet.tnear[i] = ray.tnear;
      packet.dir_x[i] = ray.dir_x;
      packet.dir_y[i] = ray.dir_y;
      packet.dir_z[i] = ray.dir_z;
      packet.time[i] = 0.0f;
      packet.tfar[i] = ray.tfar;
      packet.mask[i] = ray.mask;
      packet.id[i] = 0;
      packet.flags[i] = 0;
    }
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    P::occluded(valid, scene, &context, &packet);
    for (std::size_t i = 0; i < count; ++i) blocked[first + i] = packet.tfar[i] < 0.0f ? 1 : 0;
  }
}

}  // namespace

RayCaster::RayCaster(const std::vector<const TriMesh*>& surfaces) {
  device_ = rtcNewDevice("threads=0");
  if (!device_) throw std::runtime_error("cannot create an Embree device");
  scene_ = rtcNewScene(device_);
  rtcSetSceneFlags(scene_, RTC_SCENE_FLAG_ROBUST);
  rtcSetSceneBuildQuality(scene_, RTC_BUILD_QUALITY_HIGH);

  Vec3 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
  double magnitude = 0.0;
  for (std::size_t s = 0; s < surfaces.size(); ++s) {
    const TriMesh& mesh = *surfaces[s];
    RTCGeometry geometry = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(
        geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), mesh.n_vertices()));
    auto* indices = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
        geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), mesh.n_faces()));
    throw_on_error(device_, "allocating geometry");
    for (const auto vh : mesh.vertices()) {
      const Vec3& p = mesh.point(vh);
      for (int k = 0; k < 3; ++k) {
        vertices[3 * vh.idx() + k] = static_cast<float>(p[k]);
        magnitude = std::max(magnitude, std::abs(p[k]));
      }
      lo.minimize(p);
      hi.maximize(p);
    }
    for (const auto fh : mesh.faces()) {
      int k = 0;
      for (const auto vh : mesh.fv_range(fh)) indices[3 * fh.idx() + k++] = static_cast<unsigned>(vh.idx());
    }
    rtcCommitGeometry(geometry);
    rtcAttachGeometryByID(scene_, geometry, static_cast<unsigned>(s));
    rtcReleaseGeometry(geometry);
  }
  rtcCommitScene(scene_);
  throw_on_error(device_, "building the scene");
  diagonal_ = surfaces.empty() ? 0.0 : (hi - lo).norm();
  epsilon_ = kRelativeEpsilon * std::max({diagonal_, magnitude, 1e-30});
}

RayCaster::~RayCaster() {
  if (scene_) rtcReleaseScene(scene_);
  if (device_) rtcReleaseDevice(device_);
}

bool RayCaster::occluded(const Vec3& from, const Vec3& to) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRay ray = make_segment_ray(from, to, epsilon_);
  rtcOccluded1(scene_, &context, &ray);
  return ray.tfar < 0.0f;  // Embree marks a blocked ray with tfar = -inf
}

void RayCaster::occluded(std::span<const ShadowRay> rays, std::span<std::uint8_t> blocked) const {
  // Measured on the Cornell box (BENCHMARKS.md): a link's rays (k² ≤ 64,
  // between two elements) go fastest in packets of 16, one large batch of
  // unrelated rays as a stream.
  constexpr std::size_t kPacketBatch = 64;
  occluded(rays, blocked, rays.size() <= kPacketBatch ? ShadowQuery::kPacket16 : ShadowQuery::kStream);
}

void RayCaster::occluded(std::span<const ShadowRay> rays, std::span<std::uint8_t> blocked, ShadowQuery query) const {
  if (blocked.size() < rays.size()) throw std::invalid_argument("RayCaster::occluded: output too short");
  switch (query) {
    case ShadowQuery::kSingle:
      for (std::size_t i = 0; i < rays.size(); ++i) blocked[i] = occluded(rays[i].from, rays[i].to) ? 1 : 0;
      return;
    case ShadowQuery::kStream:
      occluded_stream(scene_, rays, blocked, epsilon_);
      return;
    case ShadowQuery::kPacket4:
      occluded_packets<Packet4>(scene_, rays, blocked, epsilon_);
      return;
    case ShadowQuery::kPacket8:
      occluded_packets<Packet8>(scene_, rays, blocked, epsilon_);
      return;
    case ShadowQuery::kPacket16:
      occluded_packets<Packet16>(scene_, rays, blocked, epsilon_);
      return;
  }
}

std::optional<RayHit> RayCaster::intersect(const Vec3& origin, const Vec3& direction) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit rayhit{};
  rayhit.ray = make_segment_ray(origin, origin + direction, 0.0);
  rayhit.ray.tfar = std::numeric_limits<float>::infinity();
  rayhit.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(scene_, &context, &rayhit);
  if (rayhit.hit.geomID == RTC_INVALID_GEOMETRY_ID) return std::nullopt;
  RayHit hit;
  hit.surface = static_cast<int>(rayhit.hit.geomID);
  hit.face = static_cast<int>(rayhit.hit.primID);
  hit.distance = rayhit.ray.tfar * direction.norm();
  hit.u = rayhit.hit.u;
  hit.v = rayhit.hit.v;
  return hit;
}

}  // namespace lhr
