#include "io/paper_scenes.hpp"

#include <algorithm>
#include <array>
#include <map>
#include <stdexcept>


namespace lhr {

namespace {

// The scenes are built in metres, y up, from axis-aligned rectangles and
// boxes. Every face is counter-clockwise seen from the open space it faces
// (docs/design.md §3: only the front side reflects and emits).

enum FaceBits : unsigned {
  kNegX = 1u << 0,
  kPosX = 1u << 1,
  kNegY = 1u << 2,
  kPosY = 1u << 3,
  kNegZ = 1u << 4,
  kPosZ = 1u << 5,
  kAllFaces = 0x3fu,
};

constexpr unsigned face_bit(int axis, int sign) { return 1u << (2 * axis + (sign > 0 ? 1 : 0)); }

struct Box {
  Vec3 lo;
  Vec3 hi;
};

// A rotation by a multiple of 90 degrees about +y followed by a translation,
// so furniture is modelled once facing -z and placed anywhere. One quarter
// turn makes it face -x, two +z, three +x.
struct Placement {
  Vec3 origin{0, 0, 0};
  int quarter_turns = 0;

  Vec3 rotate(const Vec3& p) const {
    Vec3 r = p;
    for (int i = 0; i < ((quarter_turns % 4) + 4) % 4; ++i) r = Vec3(r[2], r[1], -r[0]);
    return r;
  }
  Box apply(const Box& b) const {
    const Vec3 a = rotate(b.lo);
    const Vec3 c = rotate(b.hi);
    Vec3 lo = a;
    Vec3 hi = a;
    lo.minimize(c);
    hi.maximize(c);
    return {lo + origin, hi + origin};
  }
  unsigned apply(unsigned mask) const {
    unsigned out = 0;
    for (int axis = 0; axis < 3; ++axis) {
      for (int sign : {-1, 1}) {
        if (!(mask & face_bit(axis, sign))) continue;
        Vec3 n(0, 0, 0);
        n[axis] = sign;
        const Vec3 r = rotate(n);
        for (int a = 0; a < 3; ++a) {
          if (r[a] != 0) out |= face_bit(a, r[a] > 0 ? 1 : -1);
        }
      }
    }
    return out;
  }
};

class SoupBuilder {
 public:
  int add_material(const std::string& name, const Rgb& kd, const Rgb& ke = Rgb(0, 0, 0)) {
    Material m;
    m.name = name;
    m.reflectance = kd;
    m.emission = ke;
    soup_.materials.push_back(m);
    return static_cast<int>(soup_.materials.size()) - 1;
  }

  // Vertices are shared inside a group only: surfaces never share vertices
  // (docs/design.md §3), and faces of one group that meet along a full edge are
  // connected for the surface split.
  void begin_group(const std::string& name) {
    soup_.groups.push_back(name);
    group_vertices_.clear();
  }

  // Axis-aligned rectangle in the plane lo[axis] == hi[axis], facing
  // sign * e_axis, cut into a grid around rectangular holes (doorways,
  // windows) so the remaining quads share full edges: one surface with holes.
  void rectangle(const Box& r, int axis, int sign, int material, const std::vector<Box>& holes = {}) {
    const int u = (axis + 1) % 3;
    const int v = (axis + 2) % 3;
    std::vector<double> us{r.lo[u], r.hi[u]};
    std::vector<double> vs{r.lo[v], r.hi[v]};
    std::vector<Box> cutting;
    for (const Box& h : holes) {
      if (h.lo[axis] > r.lo[axis] || h.hi[axis] < r.lo[axis]) continue;
      const double u0 = std::max(h.lo[u], r.lo[u]);
      const double u1 = std::min(h.hi[u], r.hi[u]);
      const double v0 = std::max(h.lo[v], r.lo[v]);
      const double v1 = std::min(h.hi[v], r.hi[v]);
      if (u1 <= u0 || v1 <= v0) continue;
      us.insert(us.end(), {u0, u1});
      vs.insert(vs.end(), {v0, v1});
      cutting.push_back(h);
    }
    std::sort(us.begin(), us.end());
    us.erase(std::unique(us.begin(), us.end()), us.end());
    std::sort(vs.begin(), vs.end());
    vs.erase(std::unique(vs.begin(), vs.end()), vs.end());
    for (std::size_t i = 0; i + 1 < us.size(); ++i) {
      for (std::size_t j = 0; j + 1 < vs.size(); ++j) {
        const double uc = 0.5 * (us[i] + us[i + 1]);
        const double vc = 0.5 * (vs[j] + vs[j + 1]);
        const bool in_hole = std::any_of(cutting.begin(), cutting.end(), [&](const Box& h) {
          return uc > h.lo[u] && uc < h.hi[u] && vc > h.lo[v] && vc < h.hi[v];
        });
        if (in_hole) continue;
        auto corner = [&](double cu, double cv) {
          Vec3 p = r.lo;
          p[u] = cu;
          p[v] = cv;
          return vertex(p);
        };
        // e_u x e_v = e_axis, so this order faces +axis.
        std::vector<int> f{corner(us[i], vs[j]), corner(us[i + 1], vs[j]), corner(us[i + 1], vs[j + 1]),
                           corner(us[i], vs[j + 1])};
        if (sign < 0) std::reverse(f.begin(), f.end());
        soup_.faces.push_back(InputFace{f, material, static_cast<int>(soup_.groups.size()) - 1, 0});
      }
    }
  }

  // The faces of b selected by mask; outward for objects, inward for rooms
  // and openings (the side a viewer inside sees).
  void box(const Box& b, unsigned mask, int material, bool inward = false) {
    for (int axis = 0; axis < 3; ++axis) {
      for (int sign : {-1, 1}) {
        if (!(mask & face_bit(axis, sign))) continue;
        Box r = b;
        if (sign < 0) r.hi[axis] = b.lo[axis];
        else r.lo[axis] = b.hi[axis];
        rectangle(r, axis, inward ? -sign : sign, material);
      }
    }
  }

  PolygonSoup take() { return std::move(soup_); }

 private:
  int vertex(const Vec3& p) {
    const std::array<double, 3> key{p[0], p[1], p[2]};
    const auto it = group_vertices_.find(key);
    if (it != group_vertices_.end()) return it->second;
    soup_.points.push_back(p);
    const int index = static_cast<int>(soup_.points.size()) - 1;
    group_vertices_.emplace(key, index);
    return index;
  }

  PolygonSoup soup_;
  std::map<std::array<double, 3>, int> group_vertices_;
};

struct Palette {
  int wall, ceiling, floor, wood, dark_wood, fabric, window, light;
};

Palette make_palette(SoupBuilder& b, const Rgb& light_radiance) {
  Palette p{};
  p.wall = b.add_material("wall", Rgb(0.72, 0.7, 0.64));
  p.ceiling = b.add_material("ceiling", Rgb(0.8, 0.8, 0.8));
  p.floor = b.add_material("floor", Rgb(0.42, 0.3, 0.19));
  p.wood = b.add_material("wood", Rgb(0.55, 0.38, 0.22));
  p.dark_wood = b.add_material("dark_wood", Rgb(0.3, 0.2, 0.12));
  p.fabric = b.add_material("fabric", Rgb(0.22, 0.3, 0.5));
  p.window = b.add_material("window", Rgb(0.55, 0.65, 0.75));
  p.light = b.add_material("light", Rgb(0.8, 0.8, 0.8), light_radiance);
  return p;
}

// A room's shell seen from inside: floor, ceiling and four walls, each its own
// group, with the openings (doorways, windows) that cross a wall cut out.
void add_room(SoupBuilder& b, const Palette& pal, const std::string& name, const Box& room,
              const std::vector<Box>& openings) {
  const char* wall_names[3][2] = {{"wall_west", "wall_east"}, {"floor", "ceiling"}, {"wall_south", "wall_north"}};
  for (int axis : {1, 0, 2}) {
    for (int side = 0; side < 2; ++side) {
      b.begin_group(name + "_" + wall_names[axis][side]);
      Box r = room;
      if (side == 0) r.hi[axis] = room.lo[axis];
      else r.lo[axis] = room.hi[axis];
      const int material = axis != 1 ? pal.wall : side == 0 ? pal.floor : pal.ceiling;
      b.rectangle(r, axis, side == 0 ? 1 : -1, material, openings);
    }
  }
}

// A doorway through a wall of thickness opening.hi[axis] - opening.lo[axis]:
// threshold, two jambs and head, facing into the passage.
void add_doorway(SoupBuilder& b, const Palette& pal, const std::string& name, const Box& opening, int axis) {
  b.begin_group(name);
  const unsigned mask = kAllFaces & ~face_bit(axis, -1) & ~face_bit(axis, 1);
  b.box(opening, mask & ~kNegY, pal.wall, true);
  b.box(opening, kNegY, pal.floor, true);
}

// A window recess of the given depth behind a wall: four reveals and the pane
// at the far end, facing the room. room_side = +1 when the room lies on the
// +axis side of the recess.
void add_window(SoupBuilder& b, const Palette& pal, const std::string& name, const Box& recess, int axis,
                int room_side) {
  b.begin_group(name);
  const unsigned reveals = kAllFaces & ~face_bit(axis, -1) & ~face_bit(axis, 1);
  b.box(recess, reveals, pal.wall, true);
  b.box(recess, face_bit(axis, -room_side), pal.window, true);
}

// A thin emitting quad hanging just below the ceiling, facing down.
void add_light(SoupBuilder& b, const Palette& pal, const std::string& name, double cx, double cz, double sx,
               double sz, double ceiling_y) {
  constexpr double kDrop = 0.01;  // not coplanar with the ceiling
  b.begin_group(name);
  const double y = ceiling_y - kDrop;
  b.rectangle({Vec3(cx - sx / 2, y, cz - sz / 2), Vec3(cx + sx / 2, y, cz + sz / 2)}, 1, -1, pal.light);
}

void add_placed_box(SoupBuilder& b, const Placement& at, const std::string& group, const Box& local,
                    unsigned local_mask, int material) {
  b.begin_group(group);
  b.box(at.apply(local), at.apply(local_mask), material);
}

struct TableStyle {
  double width = 1.6;  // local x
  double depth = 0.9;  // local z
  double height = 0.75;
  double top_thickness = 0.04;
  double leg = 0.06;
  double inset = 0.05;
  bool aprons = true;
  bool stretchers = true;
};

// Top, four legs, optional aprons under the top and stretchers near the
// floor. Faces hidden against the floor or another part are left out.
void add_table(SoupBuilder& b, const Palette& pal, const std::string& name, const Placement& at,
               const TableStyle& s) {
  const double hx = s.width / 2;
  const double hz = s.depth / 2;
  const double under = s.height - s.top_thickness;
  add_placed_box(b, at, name + "_top", {Vec3(-hx, under, -hz), Vec3(hx, s.height, hz)}, kAllFaces, pal.wood);
  const double lx = hx - s.inset;  // outer faces of the legs
  const double lz = hz - s.inset;
  const std::array<std::array<double, 2>, 4> corners{{{-1, -1}, {1, -1}, {1, 1}, {-1, 1}}};
  for (int i = 0; i < 4; ++i) {
    const double x = corners[i][0] * lx;
    const double z = corners[i][1] * lz;
    const Box leg{Vec3(std::min(x, x - corners[i][0] * s.leg), 0, std::min(z, z - corners[i][1] * s.leg)),
                  Vec3(std::max(x, x - corners[i][0] * s.leg), under, std::max(z, z - corners[i][1] * s.leg))};
    add_placed_box(b, at, name + "_leg" + std::to_string(i + 1), leg, kAllFaces & ~kNegY & ~kPosY,
                   pal.dark_wood);
  }
  const double ix = lx - s.leg;  // inner faces of the legs
  const double iz = lz - s.leg;
  if (s.aprons) {
    constexpr double kHeight = 0.08;
    constexpr double kThickness = 0.02;
    const double y0 = under - kHeight;
    for (int side : {-1, 1}) {
      const double z_out = side * (lz - 0.01);
      add_placed_box(b, at, name + "_apron_z" + (side < 0 ? "n" : "p"),
                     {Vec3(-ix, y0, std::min(z_out, z_out - side * kThickness)),
                      Vec3(ix, under, std::max(z_out, z_out - side * kThickness))},
                     kNegY | kNegZ | kPosZ, pal.wood);
      const double x_out = side * (lx - 0.01);
      add_placed_box(b, at, name + "_apron_x" + (side < 0 ? "n" : "p"),
                     {Vec3(std::min(x_out, x_out - side * kThickness), y0, -iz),
                      Vec3(std::max(x_out, x_out - side * kThickness), under, iz)},
                     kNegY | kNegX | kPosX, pal.wood);
    }
  }
  if (s.stretchers) {
    constexpr double kY0 = 0.12;
    constexpr double kY1 = 0.16;
    constexpr double kThickness = 0.03;
    for (int side : {-1, 1}) {
      const double zc = side * (lz - s.leg / 2);
      add_placed_box(b, at, name + "_stretcher_z" + (side < 0 ? "n" : "p"),
                     {Vec3(-ix, kY0, zc - kThickness / 2), Vec3(ix, kY1, zc + kThickness / 2)},
                     kNegY | kPosY | kNegZ | kPosZ, pal.dark_wood);
      const double xc = side * (lx - s.leg / 2);
      add_placed_box(b, at, name + "_stretcher_x" + (side < 0 ? "n" : "p"),
                     {Vec3(xc - kThickness / 2, kY0, -iz), Vec3(xc + kThickness / 2, kY1, iz)},
                     kNegY | kPosY | kNegX | kPosX, pal.dark_wood);
    }
  }
}

// Seat on four legs with a backrest along local +z; the sitter faces -z.
void add_chair(SoupBuilder& b, const Palette& pal, const std::string& name, const Placement& at) {
  constexpr double kHalf = 0.225;
  constexpr double kSeatTop = 0.45;
  constexpr double kSeatBottom = 0.41;
  constexpr double kLeg = 0.04;
  add_placed_box(b, at, name + "_seat", {Vec3(-kHalf, kSeatBottom, -kHalf), Vec3(kHalf, kSeatTop, kHalf)},
                 kAllFaces, pal.wood);
  const std::array<std::array<double, 2>, 4> corners{{{-1, -1}, {1, -1}, {1, 1}, {-1, 1}}};
  for (int i = 0; i < 4; ++i) {
    const double x = corners[i][0] * (kHalf - 0.01);
    const double z = corners[i][1] * (kHalf - 0.01);
    const Box leg{Vec3(std::min(x, x - corners[i][0] * kLeg), 0, std::min(z, z - corners[i][1] * kLeg)),
                  Vec3(std::max(x, x - corners[i][0] * kLeg), kSeatBottom, std::max(z, z - corners[i][1] * kLeg))};
    add_placed_box(b, at, name + "_leg" + std::to_string(i + 1), leg, kAllFaces & ~kNegY & ~kPosY,
                   pal.dark_wood);
  }
  add_placed_box(b, at, name + "_back", {Vec3(-kHalf, kSeatTop, kHalf - 0.04), Vec3(kHalf, 0.9, kHalf)},
                 kAllFaces & ~kNegY, pal.wood);
}

// Two sides, shelves and a top board between them, and a back panel along
// local +z; open to -z.
void add_bookcase(SoupBuilder& b, const Palette& pal, const std::string& name, const Placement& at,
                  double width, double height, int shelves) {
  constexpr double kDepth = 0.32;
  constexpr double kBoard = 0.02;
  const double hx = width / 2;
  const double z0 = -kDepth / 2;
  const double z1 = kDepth / 2 - kBoard;
  add_placed_box(b, at, name + "_back", {Vec3(-hx, 0, z1), Vec3(hx, height, kDepth / 2)}, kAllFaces & ~kNegY,
                 pal.dark_wood);
  for (int side : {-1, 1}) {
    const double x_out = side * hx;
    const double x_in = side * (hx - kBoard);
    add_placed_box(b, at, name + (side < 0 ? "_side_left" : "_side_right"),
                   {Vec3(std::min(x_out, x_in), 0, z0), Vec3(std::max(x_out, x_in), height, z1)},
                   kAllFaces & ~kNegY & ~kPosZ, pal.wood);
  }
  // Board i at height fraction i/shelves; the last one is the top.
  for (int i = 0; i <= shelves; ++i) {
    const double y1 = i == 0 ? 0.08 : 0.08 + (height - 0.08) * i / shelves;
    const double y0 = y1 - kBoard;
    add_placed_box(b, at, name + (i == shelves ? std::string("_top") : "_shelf" + std::to_string(i + 1)),
                   {Vec3(-hx + kBoard, y0, z0), Vec3(hx - kBoard, y1, z1)}, kNegY | kPosY | kNegZ, pal.wood);
  }
}

// Base with one cushion per seat, two arms and a backrest along local +z;
// faces -z. Faces hidden against another part are left out, so no surface
// is refined where no light can reach.
void add_sofa(SoupBuilder& b, const Palette& pal, const std::string& name, const Placement& at, int seats) {
  constexpr double kSeat = 0.6;
  constexpr double kArm = 0.18;
  constexpr double kFront = -0.45;
  constexpr double kBackFront = 0.25;
  const double half = seats * kSeat / 2;
  add_placed_box(b, at, name + "_base", {Vec3(-half, 0, kFront), Vec3(half, 0.3, kBackFront)}, kNegZ, pal.fabric);
  for (int i = 0; i < seats; ++i) {
    const double x0 = -half + i * kSeat;
    add_placed_box(b, at, name + "_cushion" + std::to_string(i + 1),
                   {Vec3(x0, 0.3, kFront), Vec3(x0 + kSeat, 0.42, kBackFront)}, kPosY | kNegZ, pal.fabric);
  }
  for (int side : {-1, 1}) {
    const double x_in = side * half;
    const double x_out = side * (half + kArm);
    add_placed_box(b, at, name + (side < 0 ? "_arm_left" : "_arm_right"),
                   {Vec3(std::min(x_out, x_in), 0, kFront), Vec3(std::max(x_out, x_in), 0.6, kBackFront)},
                   kPosY | kNegZ | kNegX | kPosX, pal.fabric);
  }
  add_placed_box(b, at, name + "_back", {Vec3(-half - kArm, 0, kBackFront), Vec3(half + kArm, 0.85, 0.45)},
                 kAllFaces & ~kNegY, pal.fabric);
}

void add_cabinet(SoupBuilder& b, const Palette& pal, const std::string& name, const Placement& at, double width,
                 double depth, double height) {
  add_placed_box(b, at, name, {Vec3(-width / 2, 0, -depth / 2), Vec3(width / 2, height, depth / 2)},
                 kAllFaces & ~kNegY, pal.dark_wood);
}

// Paper §6 scene 1: two rooms joined by a doorway, four lights each, furniture.
PaperScene two_rooms() {
  constexpr double kWidth = 6.0;  // x
  constexpr double kDepth = 5.0;  // z
  constexpr double kHeight = 2.8;
  constexpr double kWall = 0.15;
  SoupBuilder b;
  const Palette pal = make_palette(b, Rgb(12, 12, 10.5));
  const Box room1{Vec3(0, 0, 0), Vec3(kWidth, kHeight, kDepth)};
  const Box room2{Vec3(kWidth + kWall, 0, 0), Vec3(2 * kWidth + kWall, kHeight, kDepth)};
  const Box door{Vec3(kWidth, 0, 2.0), Vec3(kWidth + kWall, 2.1, 3.0)};
  const Box window1{Vec3(1.8, 0.9, -kWall), Vec3(3.6, 2.2, 0)};
  const Box window2{Vec3(kWidth + kWall + 2.2, 0.9, kDepth), Vec3(kWidth + kWall + 4.2, 2.2, kDepth + kWall)};
  add_room(b, pal, "room1", room1, {door, window1});
  add_room(b, pal, "room2", room2, {door, window2});
  add_doorway(b, pal, "door", door, 0);
  add_window(b, pal, "room1_window", window1, 2, 1);
  add_window(b, pal, "room2_window", window2, 2, -1);
  for (int room = 0; room < 2; ++room) {
    const double x0 = room == 0 ? room1.lo[0] : room2.lo[0];
    int n = 0;
    for (double fx : {0.25, 0.75}) {
      for (double fz : {0.25, 0.75}) {
        add_light(b, pal, "room" + std::to_string(room + 1) + "_light" + std::to_string(++n), x0 + fx * kWidth,
                  fz * kDepth, 0.5, 0.5, kHeight);
      }
    }
  }

  // Room 1: dining table with four chairs, a bookcase and a sideboard.
  add_table(b, pal, "dining_table", {Vec3(3.0, 0, 2.5), 0}, TableStyle{1.8, 0.9});
  add_chair(b, pal, "chair1", {Vec3(2.5, 0, 1.75), 2});
  add_chair(b, pal, "chair2", {Vec3(3.5, 0, 1.75), 2});
  add_chair(b, pal, "chair3", {Vec3(2.5, 0, 3.25), 0});
  add_chair(b, pal, "chair4", {Vec3(3.5, 0, 3.25), 0});
  add_bookcase(b, pal, "bookcase1", {Vec3(0.2, 0, 1.2), 1}, 0.9, 1.9, 4);
  add_cabinet(b, pal, "sideboard", {Vec3(3.0, 0, 4.7), 0}, 1.6, 0.45, 0.85);

  // Room 2: sofa and armchair, coffee and side tables, desk with chair, a bookcase, a
  // television on its cabinet.
  const double x0 = room2.lo[0];
  add_sofa(b, pal, "sofa", {Vec3(x0 + 5.45, 0, 2.0), 1}, 3);
  add_sofa(b, pal, "armchair", {Vec3(x0 + 4.3, 0, 0.6), 2}, 1);
  add_table(b, pal, "coffee_table", {Vec3(x0 + 4.3, 0, 2.0), 1},
            TableStyle{1.1, 0.55, 0.42, 0.03, 0.05, 0.03, false, false});
  add_table(b, pal, "desk", {Vec3(x0 + 1.6, 0, 4.55), 0}, TableStyle{1.4, 0.7, 0.74, 0.04, 0.05, 0.03, true, false});
  add_chair(b, pal, "desk_chair", {Vec3(x0 + 1.6, 0, 3.95), 2});
  add_bookcase(b, pal, "bookcase2", {Vec3(x0 + 1.6, 0, 0.2), 2}, 1.2, 2.0, 4);
  add_cabinet(b, pal, "side_table", {Vec3(x0 + 5.55, 0, 0.6), 0}, 0.4, 0.4, 0.5);
  add_cabinet(b, pal, "tv_cabinet", {Vec3(x0 + 0.45, 0, 3.7), 3}, 1.0, 0.4, 0.5);
  add_placed_box(b, {Vec3(x0 + 0.45, 0, 3.7), 3}, "tv", {Vec3(-0.35, 0.5, -0.04), Vec3(0.35, 0.95, 0.04)},
                 kAllFaces & ~kNegY, pal.dark_wood);

  PaperScene scene;
  scene.soup = b.take();
  // In room 1, looking past the dining table through the doorway into room 2.
  scene.camera.eye = Vec3(0.7, 1.6, 3.9);
  scene.camera.target = Vec3(kWidth + kWall / 2, 1.0, 2.5);
  scene.camera.up = Vec3(0, 1, 0);
  scene.camera.fov_y_deg = 55.0;
  scene.camera.width = 512;
  scene.camera.height = 384;
  return scene;
}

// Paper §6 scene 2: four rooms in a 2x2 plan, two lights and one table each.
PaperScene four_rooms() {
  constexpr double kWidth = 5.0;  // x
  constexpr double kDepth = 4.0;  // z
  constexpr double kHeight = 2.7;
  constexpr double kWall = 0.15;
  SoupBuilder b;
  const Palette pal = make_palette(b, Rgb(15, 15, 13));
  auto room_box = [&](int i, int j) {
    const Vec3 lo(i * (kWidth + kWall), 0, j * (kDepth + kWall));
    return Box{lo, lo + Vec3(kWidth, kHeight, kDepth)};
  };
  // Doorways through the partition at x = kWidth (rows j) and z = kDepth (columns i).
  std::array<Box, 2> x_doors{};
  std::array<Box, 2> z_doors{};
  for (int k = 0; k < 2; ++k) {
    const double z0 = k * (kDepth + kWall) + 1.0;
    x_doors[k] = {Vec3(kWidth, 0, z0), Vec3(kWidth + kWall, 2.05, z0 + 0.9)};
    const double x0 = k * (kWidth + kWall) + 1.5;
    z_doors[k] = {Vec3(x0, 0, kDepth), Vec3(x0 + 0.9, 2.05, kDepth + kWall)};
  }
  for (int i = 0; i < 2; ++i) {
    for (int j = 0; j < 2; ++j) {
      const std::string name = "room" + std::to_string(1 + i + 2 * j);
      const Box room = room_box(i, j);
      // One window in each outer wall: the x-facing one and the z-facing one.
      const double wx = i == 0 ? room.lo[0] - kWall : room.hi[0];
      const Box window_x{Vec3(wx, 0.9, room.lo[2] + 1.2), Vec3(wx + kWall, 2.1, room.lo[2] + 2.8)};
      const double wz = j == 0 ? room.lo[2] - kWall : room.hi[2];
      const Box window_z{Vec3(room.lo[0] + 1.6, 0.9, wz), Vec3(room.lo[0] + 3.4, 2.1, wz + kWall)};
      add_room(b, pal, name, room, {x_doors[j], z_doors[i], window_x, window_z});
      add_window(b, pal, name + "_window_x", window_x, 0, i == 0 ? 1 : -1);
      add_window(b, pal, name + "_window_z", window_z, 2, j == 0 ? 1 : -1);
      const double cx = 0.5 * (room.lo[0] + room.hi[0]);
      for (int k = 0; k < 2; ++k) {
        add_light(b, pal, name + "_light" + std::to_string(k + 1), cx, room.lo[2] + (k + 1) * kDepth / 3, 1.2,
                  0.3, kHeight);
      }
      add_table(b, pal, name + "_table", {Vec3(cx, 0, 0.5 * (room.lo[2] + room.hi[2])), (i + j) % 2},
                TableStyle{1.6, 0.9});
    }
  }
  for (int k = 0; k < 2; ++k) {
    add_doorway(b, pal, "door_x" + std::to_string(k + 1), x_doors[k], 0);
    add_doorway(b, pal, "door_z" + std::to_string(k + 1), z_doors[k], 2);
  }

  PaperScene scene;
  scene.soup = b.take();
  // Inside room 1 (x, z in [0,5] x [0,4]), looking at its table: the other
  // three rooms are hidden except through a doorway.
  scene.camera.eye = Vec3(0.5, 1.6, 0.5);
  scene.camera.target = Vec3(3.0, 0.8, 2.4);
  scene.camera.up = Vec3(0, 1, 0);
  scene.camera.fov_y_deg = 55.0;
  scene.camera.width = 512;
  scene.camera.height = 384;
  return scene;
}

}  // namespace

std::vector<std::string> paper_scene_names() { return {"two-rooms", "four-rooms"}; }

PaperScene make_paper_scene(const std::string& name) {
  if (name == "two-rooms") return two_rooms();
  if (name == "four-rooms") return four_rooms();
  std::string names;
  for (const std::string& n : paper_scene_names()) names += (names.empty() ? "" : ", ") + n;
  throw std::invalid_argument("unknown scene '" + name + "' (known: " + names + ")");
}

}  // namespace lhr
