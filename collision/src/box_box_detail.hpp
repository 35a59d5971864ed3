// Internals of the box-box contact path shared by box_box.cpp (SAT, the
// axis choice, the answer and its cache) and box_face.cpp (the face
// clipping, the reduction to four points, the feature ids and the rounded
// exits): the unit box's numbering, a box placed in A's core frame, the pair.
#pragma once

#include <Eigen/Core>
#include <array>
#include <hedra/collision/detail/sat.hpp>
#include <hedra/collision/manifold.hpp>

namespace hedra::collision::detail::box_box {

using Vec = Eigen::Vector3d;
using hull::Index;

// The unit box mesh's numbering (sat.hpp's unit_box_mesh()), read once.
struct BoxTopology {
  std::array<std::array<Index, 4>, 6> face_vertex;  // face f's corners in face_edges order
  std::array<std::array<Index, 4>, 6> face_edge;    // the half-edges leaving them
  std::array<std::array<Index, 3>, 8> vertex_face;  // vertex_faces order
  std::array<Index, 24> twin;
  std::array<Index, 24> origin;
  std::array<Index, 64> edge_between;  // [8 v0 + v1]: the half-edge v0 -> v1
  std::array<Vec, 6> normal;           // unit outward normals (axis vectors)
  // Face f's side plane k (through corner k and k + 1, swept along the
  // normal) is side_sign[f][k] * x[side_axis[f][k]] = const.
  std::array<std::array<int, 4>, 6> side_axis;
  std::array<std::array<double, 4>, 6> side_sign;
};

// The unit box mesh's numbering, built on first use (thread-safe).
const BoxTopology& topology();

inline Vec corner(const Vec& h, Index v) {
  return {(v & 1) ? h.x() : -h.x(), (v & 2) ? h.y() : -h.y(), (v & 4) ? h.z() : -h.z()};
}

// A box's vertex maximising d . x (sign bits, ties to +, as SatPolytope).
inline Index support(const Vec& d) {
  return static_cast<Index>((d.x() >= 0 ? 1 : 0) | (d.y() >= 0 ? 2 : 0) | (d.z() >= 0 ? 4 : 0));
}

// One box of the pair, placed in A's core frame: x -> rotation x + translation.
struct Side {
  Vec h;
  const Eigen::Matrix3d* rotation;  // null: A itself (identity)
  const Vec* translation;
  Vec point(Index v) const {
    const Vec c = corner(h, v);
    return rotation ? Vec(*rotation * c + *translation) : c;
  }
  Vec direction(const Vec& d) const { return rotation ? Vec(*rotation * d) : d; }
  Vec local_direction(const Vec& d) const { return rotation ? Vec(rotation->transpose() * d) : d; }
};

struct Pair {
  Vec ha, hb;
  double ra, rb;
  RelativePose rel;
  double scale, band, keep, core_contact, tolerance, hold;
  const ContactCache* last;
  Side side_a() const { return {ha, nullptr, nullptr}; }
  Side side_b() const { return {hb, &rel.rotation, &rel.translation}; }
};

struct Candidate {
  Vec on_a, on_b;
  double separation;
  FeatureId id;
};

// A polygon of at most 4 + 4 points (a quadrilateral clipped by 4 planes),
// each point with where it comes from: `origin` 0..3 the incident corner k
// as is, 8 + L a crossing on the segment labelled L; `next` the label of the
// segment leaving it (0..3 incident edge k, from corner k to k + 1; 4 + j
// the side plane j). Labels name the clipped points as contact_clip.cpp's
// geometric tests do (a crossing on incident edge k is that edge's), without
// the searches.
constexpr int kMaxPolygon = 8;
struct Polygon {
  std::array<Vec, kMaxPolygon> p;
  std::array<int, kMaxPolygon> origin, next;
  int count = 0;
};

// contact_clip.cpp's reduce (box_face.cpp): the deepest, the farthest from it,
// the largest positive and negative triangle areas about n, each the first
// within ties, of points p (on B) with separations s; indices go to keep,
// their number is returned.
int reduce(const Vec* p, const double* s, int count, const Vec& n, double depth_tie, double length_tie,
           std::array<int, kMaxContactPoints>& keep);

// contact_clip.cpp's exit_distance for a box (box_face.cpp): how far the ray
// p + t d from face f of the core runs inside the core grown by r.
double exit_distance(const Side& box, Index f, const Vec& p, const Vec& d, double r);

// The face contact on reference face `ref_face` of `ref` (A when ref_is_a)
// with the incident face of `inc` (contact_clip.cpp's face_contact along the
// face normal). Candidates (at most four, ids set) go to `out`.
class FaceClipper {
 public:
  // `along` (A's frame, out of the reference, unit; null: the face's normal)
  // is the direction the points are measured along: the side planes are
  // swept along it and each separation is the gap along it.
  FaceClipper(const Pair& pair, const Side& ref, const Side& inc, Index ref_face, bool ref_is_a,
              const Vec* along = nullptr)
      : pair_(pair), ref_(ref), inc_(inc), ref_face_(ref_face), ref_is_a_(ref_is_a), along_(along) {}

  // False when the general path must answer (a non-finite crossing).
  bool run(double max_separation, Candidate* out, int& out_count, int& clipped);

 private:
  void incident_face();
  FeatureId id_of(int i, const Vec& on_ref) const;  // of clipped point i
  void side_planes();
  const Polygon* clip_by_sides(Polygon& a, Polygon& b) const;
  int hold_last(const Vec* p, const double* sep, const int* from, int count, std::array<int, kMaxContactPoints>& keep,
                int kept) const;
  bool same_as_last(const std::array<FeatureId, kMaxContactPoints>& ids, int kept) const;

 public:
  Index incident() const { return inc_face_; }

 private:
  const BoxTopology& topo_ = topology();
  const Pair& pair_;
  const Side& ref_;
  const Side& inc_;
  Index ref_face_;
  bool ref_is_a_;
  const Vec* along_;
  bool axis_aligned_ = false;  // a face of A swept along its normal: side planes +-e_i . x = h_i
  Vec n_;                      // A's frame, out of the reference face
  Vec u_;                      // the sweep: along_ or n_
  Index inc_face_ = 0;
  std::array<Vec, 4> incident_;  // the incident face's corners (A's frame)
  std::array<Vec, 4> ref_corner_;
  std::array<Vec, 4> side_normal_;  // side planes of the reference face's edges
  std::array<double, 4> side_offset_;
  std::array<int, 4> side_axis_{};  // axis_aligned_: side plane k is +-e_i, i = side_axis_[k]
  const Polygon* clipped_ = nullptr;
};

}  // namespace hedra::collision::detail::box_box
