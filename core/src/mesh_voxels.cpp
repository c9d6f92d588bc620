// The boundary surface of a voxel set as a watertight triangle mesh.
//
// 1. Unit faces: every side of a voxel whose neighbour is outside the set.
// 2. Vertex identities: around each lattice corner the unit faces are linked
//    across their edges. Where four faces meet at an edge (two voxels touching
//    only along it), each face is linked to the other face of its own voxel.
//    Linked (face, corner) pairs share one vertex (union-find). Where the two
//    voxels are also connected around both ends of such an edge, both pairs
//    would get the same two vertices: the edge gets a midpoint vertex per
//    pair instead. So every edge belongs to exactly two triangles.
// 3. Coplanar unit faces with the same outward direction are merged into
//    rectangles (greedy, row by row). A rectangle's sides keep each boundary
//    vertex that is a corner of some rectangle, which is exactly the set of
//    vertices the neighbouring rectangles need there: no T-junctions.
// 4. Each rectangle polygon is triangulated by clipping ears at its corners,
//    which never produces a zero-area triangle.
#include <algorithm>
#include <array>
#include <cstdint>
#include <memory>
#include <numeric>
#include <stdexcept>
#include <tuple>
#include <unordered_map>
#include <vector>

#include "lom/export.hpp"
#include "voxel_index.hpp"

namespace lom {

namespace {

constexpr int kKeyOffset = 32768;  // OctoMap's key of the cell starting at coordinate 0

using Int3 = VoxelIndex::Cell;

// Direction d in 0..5: axis d / 2, positive for even d.
int axisOf(int dir) { return dir >> 1; }
int signOf(int dir) { return (dir & 1) ? -1 : 1; }
int dirOf(int axis, int sign) { return axis * 2 + (sign < 0 ? 1 : 0); }

// Corner offsets (along u, w) in counter-clockwise order seen from outside.
// u = (a + 1) % 3 and w = (a + 2) % 3 form a right-handed frame with the face
// axis a, so the order is reversed for faces pointing along -a.
constexpr int kCornersPositive[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
constexpr int kCornersNegative[4][2] = {{0, 0}, {0, 1}, {1, 1}, {1, 0}};
using CornerTable = const int (*)[2];

struct UnitFace {
  Int3 voxel;
  int dir;
};

class UnionFind {
 public:
  explicit UnionFind(size_t n) : parent_(n) { std::iota(parent_.begin(), parent_.end(), 0u); }
  std::uint32_t find(std::uint32_t x) {
    while (parent_[x] != x) {
      parent_[x] = parent_[parent_[x]];
      x = parent_[x];
    }
    return x;
  }
  void unite(std::uint32_t a, std::uint32_t b) {
    a = find(a);
    b = find(b);
    if (a != b) parent_[std::max(a, b)] = std::min(a, b);
  }
  // Every element's root, in one pass (roots are the smallest members, so
  // an element's parent is settled before the element).
  std::vector<std::uint32_t> roots() && {
    for (std::uint32_t x = 0; x < parent_.size(); ++x) parent_[x] = parent_[parent_[x]];
    return std::move(parent_);
  }

 private:
  std::vector<std::uint32_t> parent_;
};

class VoxelSurfaceBuilder {
 public:
  VoxelSurfaceBuilder(const std::vector<VoxelKey>& keys, double resolution)
      : resolution_(resolution), voxels_(keys) {
    collectFaces();
  }

  SurfaceMesh build(bool merge) {
    linkCorners();
    splitDoubledEdges();
    numberVertices();
    const auto rectangles = mergeFaces(merge);
    // Pass 1: which vertices are rectangle corners (or pinned on an edge
    // where two voxels touch, which must stay split into unit segments).
    std::vector<char> is_corner = std::move(pinned_);  // by vertex number since numberVertices
    for (const Rectangle& r : rectangles)
      for (const auto& q : r.cornerPoints()) is_corner[vertexAt(r, q)] = 1;
    // Pass 2: polygons with the corner vertices of neighbours on their sides.
    SurfaceMesh mesh;
    std::vector<std::uint32_t> output_index(vertex_count_ + midpoint_positions_.size(), kNone);
    std::vector<std::uint32_t> polygon;
    std::vector<std::array<int, 2>> plane_points;  // doubled lattice coordinates in the plane
    const auto emit = [&](std::uint32_t vertex, const Int3& doubled, const std::array<int, 2>& q2) {
      if (output_index[vertex] == kNone) {
        output_index[vertex] = static_cast<std::uint32_t>(mesh.vertices.size());
        mesh.vertices.push_back(world(doubled));
      }
      polygon.push_back(output_index[vertex]);
      plane_points.push_back(q2);
    };
    for (const Rectangle& r : rectangles) {
      polygon.clear();
      plane_points.clear();
      const auto perimeter = r.perimeter();
      for (size_t i = 0; i < perimeter.size(); ++i) {
        const auto& q = perimeter[i];
        const std::uint32_t vertex = vertexAt(r, q);
        if (r.isCorner(q) || is_corner[vertex]) {
          const Int3 p = r.latticePoint(q);
          emit(vertex, {2 * p[0], 2 * p[1], 2 * p[2]}, {2 * q[0], 2 * q[1]});
        }
        if (midpoints_.empty()) continue;
        const auto& next = perimeter[(i + 1) % perimeter.size()];
        const std::uint32_t mid = midpointOn(r, q, next);
        if (mid != kNone)
          emit(mid, midpoint_positions_[mid - vertex_count_], {q[0] + next[0], q[1] + next[1]});
      }
      triangulateConvex(polygon, plane_points, mesh.triangles);
    }
    return mesh;
  }

 private:
  static constexpr std::uint32_t kNone = 0xffffffffu;

  // A merged rectangle of unit faces: cells [u0, u0 + nu) x [w0, w0 + nw) of
  // the plane at lattice coordinate `plane` along axis a.
  struct Rectangle {
    int dir = 0;
    int plane = 0;
    int u0 = 0, w0 = 0, nu = 1, nw = 1;

    [[nodiscard]] int a() const { return axisOf(dir); }
    [[nodiscard]] int u() const { return (a() + 1) % 3; }
    [[nodiscard]] int w() const { return (a() + 2) % 3; }
    [[nodiscard]] bool isCorner(const std::array<int, 2>& q) const {
      return (q[0] == u0 || q[0] == u0 + nu) && (q[1] == w0 || q[1] == w0 + nw);
    }
    [[nodiscard]] std::array<std::array<int, 2>, 4> cornerPoints() const {
      return {{{u0, w0}, {u0 + nu, w0}, {u0 + nu, w0 + nw}, {u0, w0 + nw}}};
    }
    // Lattice points along the sides, counter-clockwise seen from outside.
    [[nodiscard]] std::vector<std::array<int, 2>> perimeter() const {
      std::vector<std::array<int, 2>> points;
      points.reserve(static_cast<size_t>(2 * (nu + nw)));
      const int u1 = u0 + nu, w1 = w0 + nw;
      if (signOf(dir) > 0) {
        for (int u = u0; u < u1; ++u) points.push_back({u, w0});
        for (int w = w0; w < w1; ++w) points.push_back({u1, w});
        for (int u = u1; u > u0; --u) points.push_back({u, w1});
        for (int w = w1; w > w0; --w) points.push_back({u0, w});
      } else {
        for (int w = w0; w < w1; ++w) points.push_back({u0, w});
        for (int u = u0; u < u1; ++u) points.push_back({u, w1});
        for (int w = w1; w > w0; --w) points.push_back({u1, w});
        for (int u = u1; u > u0; --u) points.push_back({u, w0});
      }
      return points;
    }
    [[nodiscard]] Int3 latticePoint(const std::array<int, 2>& q) const {
      Int3 p{};
      p[static_cast<size_t>(a())] = plane;
      p[static_cast<size_t>(u())] = q[0];
      p[static_cast<size_t>(w())] = q[1];
      return p;
    }
    // The voxel whose face is cell (cu, cw) of this plane.
    [[nodiscard]] Int3 voxelOfCell(int cu, int cw) const {
      Int3 v{};
      v[static_cast<size_t>(a())] = plane - (signOf(dir) > 0 ? 1 : 0);
      v[static_cast<size_t>(u())] = cu;
      v[static_cast<size_t>(w())] = cw;
      return v;
    }
  };

  [[nodiscard]] bool contains(const Int3& cell) const {
    return voxels_.rankOf(cell) != VoxelIndex::kAbsent;
  }

  // A voxel's faces are numbered in direction order from its first face.
  [[nodiscard]] std::uint32_t faceIndex(const Int3& voxel, int dir) const {
    const std::uint32_t rank = voxels_.rankOf(voxel);
    if (rank == VoxelIndex::kAbsent) return kNone;
    const unsigned mask = face_mask_[rank];
    if (!((mask >> dir) & 1u)) return kNone;
    return first_face_[rank] + static_cast<std::uint32_t>(bitCount(mask & ((1u << dir) - 1u)));
  }

  void collectFaces() {
    const std::vector<Int3>& cells = voxels_.cells();
    face_mask_.assign(cells.size(), 0);
    first_face_.resize(cells.size());
    faces_.reserve(cells.size() * 3);
    for (size_t rank = 0; rank < cells.size(); ++rank) {
      const Int3& v = cells[rank];
      first_face_[rank] = static_cast<std::uint32_t>(faces_.size());
      for (int dir = 0; dir < 6; ++dir) {
        Int3 n = v;
        n[static_cast<size_t>(axisOf(dir))] += signOf(dir);
        if (contains(n)) continue;
        face_mask_[rank] = static_cast<std::uint8_t>(face_mask_[rank] | (1u << dir));
        faces_.push_back({v, dir});
      }
    }
  }

  [[nodiscard]] static CornerTable cornerTable(int dir) {
    return signOf(dir) > 0 ? kCornersPositive : kCornersNegative;
  }

  [[nodiscard]] static Int3 cornerPoint(const UnitFace& f, int corner) {
    const int a = axisOf(f.dir), u = (a + 1) % 3, w = (a + 2) % 3;
    Int3 p = f.voxel;
    p[static_cast<size_t>(a)] += signOf(f.dir) > 0 ? 1 : 0;
    p[static_cast<size_t>(u)] += cornerTable(f.dir)[corner][0];
    p[static_cast<size_t>(w)] += cornerTable(f.dir)[corner][1];
    return p;
  }

  // The face on the other side of edge (corner j, corner j + 1) of face f.
  [[nodiscard]] std::uint32_t partnerAcrossEdge(const UnitFace& f, int j) const {
    const int a = axisOf(f.dir), u = (a + 1) % 3, w = (a + 2) % 3;
    const auto* corners = cornerTable(f.dir);
    const int k = (j + 1) % 4;
    // In-plane direction from the face towards the edge.
    Int3 c{0, 0, 0};
    c[static_cast<size_t>(u)] = corners[j][0] + corners[k][0] - 1;
    c[static_cast<size_t>(w)] = corners[j][1] + corners[k][1] - 1;
    const int c_axis = c[static_cast<size_t>(u)] != 0 ? u : w;
    const int c_sign = c[static_cast<size_t>(c_axis)];
    Int3 beside = f.voxel;  // V + c
    beside[static_cast<size_t>(c_axis)] += c_sign;
    Int3 diagonal = beside;  // V + d + c
    diagonal[static_cast<size_t>(a)] += signOf(f.dir);
    std::uint32_t g;
    if (contains(beside) && contains(diagonal)) {
      g = faceIndex(diagonal, dirOf(c_axis, -c_sign));  // concave edge
    } else if (contains(beside)) {
      g = faceIndex(beside, f.dir);  // flat
    } else {
      g = faceIndex(f.voxel, dirOf(c_axis, c_sign));  // convex, or voxels touching along the edge
    }
    if (g == kNone) throw std::logic_error("voxelSurface: inconsistent face set");
    return g;
  }

  // The linked (face, corner) pairs numbered 0, 1, ... in the order of their
  // first pair: a vertex's tables (corner flags, output index) take one
  // entry per vertex instead of one per pair, a quarter of the memory the
  // passes over the rectangles reach into at random. Midpoint vertices
  // follow the numbered ones. The pinned flags move to the new numbers.
  void numberVertices() {
    vertex_ = std::move(*links_).roots();
    links_.reset();
    std::vector<char> pinned(vertex_.size(), 0);
    std::uint32_t count = 0;
    for (std::uint32_t i = 0; i < vertex_.size(); ++i) {
      const std::uint32_t root = vertex_[i];  // <= i: numbered already when root < i
      if (root == i) {
        pinned[count] = pinned_[i];
        vertex_[i] = count++;
      } else {
        vertex_[i] = vertex_[root];
      }
    }
    pinned.resize(count);
    pinned_ = std::move(pinned);
    vertex_count_ = count;
  }

  void linkCorners() {
    links_ = std::make_unique<UnionFind>(faces_.size() * 4);
    for (std::uint32_t i = 0; i < faces_.size(); ++i) {
      const UnitFace& f = faces_[i];
      for (int j = 0; j < 4; ++j) {
        const std::uint32_t g = partnerAcrossEdge(f, j);
        for (const int corner : {j, (j + 1) % 4}) {
          const Int3 p = cornerPoint(f, corner);
          for (int m = 0; m < 4; ++m) {
            if (cornerPoint(faces_[g], m) == p) {
              links_->unite(i * 4 + static_cast<std::uint32_t>(corner),
                            g * 4 + static_cast<std::uint32_t>(m));
              break;
            }
          }
        }
      }
    }
  }

  // Vertex (union-find root) of face `face` at lattice point p, one of its corners.
  [[nodiscard]] std::uint32_t vertexOfFace(std::uint32_t face, const Int3& p) const {
    for (int m = 0; m < 4; ++m)
      if (cornerPoint(faces_[face], m) == p)
        return links_->find(face * 4 + static_cast<std::uint32_t>(m));
    throw std::logic_error("voxelSurface: point is not a corner of the face");
  }

  // Edge index j (corners j, j + 1) of `face` between lattice points p and q.
  [[nodiscard]] int edgeOfFace(std::uint32_t face, const Int3& p, const Int3& q) const {
    return edgeOfFace(faces_[face], p, q);
  }
  [[nodiscard]] static int edgeOfFace(const UnitFace& face, const Int3& p, const Int3& q) {
    for (int j = 0; j < 4; ++j) {
      const Int3 a = cornerPoint(face, j), b = cornerPoint(face, (j + 1) % 4);
      if ((a == p && b == q) || (a == q && b == p)) return j;
    }
    throw std::logic_error("voxelSurface: segment is not an edge of the face");
  }

  // Two voxels touching along an edge give four faces there, paired per voxel.
  // When both pairs end up with the same vertices at both ends (the voxels are
  // also connected around both ends), the edge would carry four triangles: it
  // gets a midpoint vertex per pair, so each half edge belongs to one pair.
  void splitDoubledEdges() {
    pinned_.assign(faces_.size() * 4, 0);
    midpoint_edges_.assign(faces_.size(), 0);
    for (std::uint32_t i = 0; i < faces_.size(); ++i) {
      const UnitFace& f = faces_[i];
      const int a = axisOf(f.dir), u = (a + 1) % 3, w = (a + 2) % 3;
      const auto* corners = cornerTable(f.dir);
      for (int j = 0; j < 4; ++j) {
        if ((midpoint_edges_[i] >> j) & 1u) continue;
        const int k = (j + 1) % 4;
        const int cu = corners[j][0] + corners[k][0] - 1, cw = corners[j][1] + corners[k][1] - 1;
        const int c_axis = cu != 0 ? u : w, c_sign = cu != 0 ? cu : cw;
        Int3 beside = f.voxel;
        beside[static_cast<size_t>(c_axis)] += c_sign;
        Int3 diagonal = beside;
        diagonal[static_cast<size_t>(a)] += signOf(f.dir);
        if (contains(beside) || !contains(diagonal)) continue;  // not two voxels touching along it
        const Int3 p = cornerPoint(f, j), q = cornerPoint(f, k);
        // Keeping both ends of every such segment keeps the vertices that tell
        // the two pairs apart, even when the segment lies inside a merged side.
        pinned_[links_->find(i * 4 + static_cast<std::uint32_t>(j))] = 1;
        pinned_[links_->find(i * 4 + static_cast<std::uint32_t>(k))] = 1;
        const std::uint32_t mate = faceIndex(f.voxel, dirOf(c_axis, c_sign));
        const std::uint32_t other = faceIndex(diagonal, dirOf(c_axis, -c_sign));
        const std::uint32_t other_mate = faceIndex(diagonal, dirOf(a, -signOf(f.dir)));
        if (vertexOfFace(i, p) != vertexOfFace(other, p) ||
            vertexOfFace(i, q) != vertexOfFace(other, q))
          continue;
        const Int3 doubled{p[0] + q[0], p[1] + q[1], p[2] + q[2]};
        const std::uint32_t base = static_cast<std::uint32_t>(faces_.size() * 4);
        const std::uint32_t mid_a = base + static_cast<std::uint32_t>(midpoint_positions_.size());
        midpoint_positions_.push_back(doubled);
        const std::uint32_t mid_b = base + static_cast<std::uint32_t>(midpoint_positions_.size());
        midpoint_positions_.push_back(doubled);
        for (const auto& [face, mid] : {std::pair{i, mid_a}, std::pair{mate, mid_a},
                                        std::pair{other, mid_b}, std::pair{other_mate, mid_b}}) {
          const int edge = edgeOfFace(face, p, q);
          midpoints_[face * 4 + static_cast<std::uint64_t>(edge)] = mid;
          midpoint_edges_[face] = static_cast<std::uint8_t>(midpoint_edges_[face] | (1u << edge));
        }
      }
    }
  }

  // The midpoint vertex on the unit segment qa-qb of rectangle r's side, if any.
  [[nodiscard]] std::uint32_t midpointOn(const Rectangle& r, const std::array<int, 2>& qa,
                                         const std::array<int, 2>& qb) const {
    int cu = std::min(qa[0], qb[0]), cw = std::min(qa[1], qb[1]);
    if (cu == r.u0 + r.nu) --cu;
    if (cw == r.w0 + r.nw) --cw;
    const Int3 voxel = r.voxelOfCell(cu, cw);
    const std::uint32_t face = faceIndex(voxel, r.dir);
    if (!midpoint_edges_[face]) return kNone;  // most faces: no need to find the edge
    const int j = edgeOfFace(UnitFace{voxel, r.dir}, r.latticePoint(qa), r.latticePoint(qb));
    if (!((midpoint_edges_[face] >> j) & 1u)) return kNone;
    const auto it = midpoints_.find(face * 4 + static_cast<std::uint64_t>(j));
    if (it == midpoints_.end()) return kNone;
    return vertex_count_ + (it->second - static_cast<std::uint32_t>(faces_.size() * 4));
  }

  // Vertex number of lattice point q on the boundary of rectangle r.
  [[nodiscard]] std::uint32_t vertexAt(const Rectangle& r, const std::array<int, 2>& q) const {
    const int cu = q[0] == r.u0 + r.nu ? q[0] - 1 : q[0];
    const int cw = q[1] == r.w0 + r.nw ? q[1] - 1 : q[1];
    const std::uint32_t face = faceIndex(r.voxelOfCell(cu, cw), r.dir);
    const auto* corners = cornerTable(r.dir);
    for (int m = 0; m < 4; ++m)
      if (corners[m][0] == q[0] - cu && corners[m][1] == q[1] - cw)
        return vertex_[face * 4 + static_cast<std::uint32_t>(m)];
    throw std::logic_error("voxelSurface: point outside its cell");
  }

  [[nodiscard]] std::vector<Rectangle> mergeFaces(bool merge) const {
    // Faces sorted by direction, plane, then row (w) and column (u).
    struct Entry {
      int dir, plane, w, u;
      std::uint32_t face;
    };
    std::vector<Entry> entries;
    entries.reserve(faces_.size());
    for (std::uint32_t i = 0; i < faces_.size(); ++i) {
      const UnitFace& f = faces_[i];
      const int a = axisOf(f.dir);
      entries.push_back({f.dir, f.voxel[static_cast<size_t>(a)] + (signOf(f.dir) > 0 ? 1 : 0),
                         f.voxel[static_cast<size_t>((a + 2) % 3)],
                         f.voxel[static_cast<size_t>((a + 1) % 3)], i});
    }
    std::sort(entries.begin(), entries.end(), [](const Entry& x, const Entry& y) {
      return std::tie(x.dir, x.plane, x.w, x.u) < std::tie(y.dir, y.plane, y.w, y.u);
    });
    std::vector<char> used(faces_.size(), 0);
    std::vector<Rectangle> rectangles;
    rectangles.reserve(merge ? faces_.size() / 2 : faces_.size());
    for (const Entry& e : entries) {
      if (used[e.face]) continue;
      Rectangle r;
      r.dir = e.dir;
      r.plane = e.plane;
      r.u0 = e.u;
      r.w0 = e.w;
      const auto freeCell = [&](int cu, int cw) {
        const std::uint32_t f = faceIndex(r.voxelOfCell(cu, cw), r.dir);
        return f != kNone && !used[f];
      };
      if (merge) {
        while (freeCell(r.u0 + r.nu, r.w0)) ++r.nu;
        for (;;) {
          bool row_free = true;
          for (int du = 0; du < r.nu && row_free; ++du) row_free = freeCell(r.u0 + du, r.w0 + r.nw);
          if (!row_free) break;
          ++r.nw;
        }
      }
      for (int dw = 0; dw < r.nw; ++dw)
        for (int du = 0; du < r.nu; ++du)
          used[faceIndex(r.voxelOfCell(r.u0 + du, r.w0 + dw), r.dir)] = 1;
      rectangles.push_back(r);
    }
    return rectangles;
  }

  // World position of a point given in doubled lattice coordinates.
  [[nodiscard]] Eigen::Vector3d world(const Int3& doubled) const {
    return {(0.5 * doubled[0] - kKeyOffset) * resolution_,
            (0.5 * doubled[1] - kKeyOffset) * resolution_,
            (0.5 * doubled[2] - kKeyOffset) * resolution_};
  }

  // Ear clipping of a convex polygon whose sides may hold extra collinear
  // points: only ears at true corners are cut, and never one that would leave
  // all remaining points on a line. Triangles keep the polygon's orientation.
  static void triangulateConvex(const std::vector<std::uint32_t>& polygon,
                                const std::vector<std::array<int, 2>>& points,
                                std::vector<std::array<std::uint32_t, 3>>& triangles) {
    std::vector<size_t> ring(polygon.size());
    std::iota(ring.begin(), ring.end(), size_t{0});
    const auto cross = [&](size_t p, size_t q, size_t r) {
      const long ax = points[q][0] - points[p][0], ay = points[q][1] - points[p][1];
      const long bx = points[r][0] - points[q][0], by = points[r][1] - points[q][1];
      return ax * by - ay * bx;
    };
    size_t at = 0;
    while (ring.size() > 3) {
      bool clipped = false;
      for (size_t tries = 0; tries < ring.size() && !clipped;
           ++tries, at = (at + 1) % ring.size()) {
        const size_t n = ring.size();
        const size_t prev = ring[(at + n - 1) % n], cur = ring[at], next = ring[(at + 1) % n];
        if (cross(prev, cur, next) == 0) continue;
        bool remainder_flat = true;
        for (size_t m = 0; m < n && remainder_flat; ++m) {
          const size_t other = ring[m];
          if (other != prev && other != cur && other != next && cross(prev, next, other) != 0)
            remainder_flat = false;
        }
        if (remainder_flat) continue;
        triangles.push_back({polygon[prev], polygon[cur], polygon[next]});
        ring.erase(ring.begin() + static_cast<std::ptrdiff_t>(at));
        if (at >= ring.size()) at = 0;
        clipped = true;
      }
      if (!clipped) throw std::logic_error("voxelSurface: polygon cannot be triangulated");
    }
    triangles.push_back({polygon[ring[0]], polygon[ring[1]], polygon[ring[2]]});
  }

  double resolution_;
  VoxelIndex voxels_;
  // Per voxel (by rank): which of its six sides are faces, and its first face.
  std::vector<std::uint8_t> face_mask_;
  std::vector<std::uint32_t> first_face_;
  std::vector<UnitFace> faces_;
  std::unique_ptr<UnionFind> links_;
  // Midpoint vertices of doubled edges: (face * 4 + edge) -> vertex id
  // (ids from faces_.size() * 4 on), and their doubled lattice positions.
  std::unordered_map<std::uint64_t, std::uint32_t> midpoints_;
  std::vector<std::uint8_t> midpoint_edges_;  // per face: the edges with a midpoint vertex
  std::vector<std::uint32_t> vertex_;         // per (face, corner): its vertex number, once linked
  std::uint32_t vertex_count_ = 0;
  std::vector<Int3> midpoint_positions_;
  std::vector<char> pinned_;  // per vertex: an end of a segment where two voxels touch
};

}  // namespace

SurfaceMesh voxelSurface(const std::vector<VoxelKey>& keys, double resolution,
                         const VoxelSurfaceOptions& options) {
  if (!(resolution > 0.0)) throw std::invalid_argument("voxelSurface: resolution must be > 0");
  VoxelSurfaceBuilder builder(keys, resolution);
  return builder.build(options.merge_coplanar);
}

}  // namespace lom
