// Finding the face a point lies farthest in front of, without scanning every
// face: used by max_outside_distance() on a finished mesh and by quickhull on
// its working structure (to catch points that merging left outside). For an
// interior point c, the exit face of the ray c -> p maximises a linear
// function of the polar dual's vertex, so hill-climbing over face adjacency
// finds it (derivation: docs/design.md, hull); the faces seeing p around it
// are then walked for the largest distance. The exit face does not change
// under an affine map of space, so directions are sorted into the start
// cells, and the early-out ellipsoid is fitted, in coordinates where the
// hull's vertex spread is round: a slab 1e-9 thick is then no harder than a
// ball (a sphere around c would be 1e-9 wide, and cells of raw directions
// would start every climb on the slab's top or bottom, far from the rim).
// Optionally each cell also carries a certified inner radius (a lower bound
// of the surface's distance along its directions), for callers that ignore
// distances of a few eps: a slab's cells are inside far beyond the ellipsoid.
//
// Adapter requirements (A):
//   std::size_t face_count() const;   bool live(Index f) const;
//   const Eigen::Vector3d& normal(Index f) const;   double offset(Index f) const;
//   template <class Fn> void for_each_neighbor(Index f, Fn&& fn) const;   // across edges
//   template <class Fn> void for_each_corner_face(Index f, Fn&& fn) const;  // around f's vertices
#pragma once

#include <algorithm>
#include <cmath>
#include <hedra/hull/half_edge_mesh.hpp>
#include <limits>
#include <utility>
#include <vector>

namespace hedra::hull::detail {

// A map x -> R x under which a hull looks round: rows u_i / w_i for three
// orthonormal directions, the normal of its largest face (across which a
// flat hull is thin), the direction across it to the vertex farthest from c,
// and the third; w_i the hull's width along u_i (from the vertices, so a
// slab 1e-9 thick gets its width to 1e-16; a covariance's eigenvalues would
// not resolve it).
inline Eigen::Matrix3d rounding_map(const std::vector<Eigen::Vector3d>& vertices, const Eigen::Vector3d& c,
                                    const Eigen::Vector3d& largest_face_normal) {
  Eigen::Matrix3d u;
  u.row(0) = largest_face_normal.normalized();
  Eigen::Vector3d across = Eigen::Vector3d::Zero();
  for (const auto& v : vertices) {
    const Eigen::Vector3d d = (v - c) - u.row(0).dot(v - c) * u.row(0).transpose();
    if (d.squaredNorm() > across.squaredNorm()) across = d;
  }
  if (!u.row(0).allFinite() || !(across.norm() > 0)) return Eigen::Matrix3d::Identity();
  u.row(1) = across.normalized();
  u.row(2) = u.row(0).cross(u.row(1)).normalized();
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  for (const auto& v : vertices) {
    const Eigen::Vector3d x = u * v;
    lo = lo.cwiseMin(x), hi = hi.cwiseMax(x);
  }
  const Eigen::Vector3d width = hi - lo;
  if (!(width.minCoeff() > 0) || !width.allFinite()) return Eigen::Matrix3d::Identity();
  return width.cwiseInverse().asDiagonal() * u;
}

template <class A>
class OutsideSearch {
 public:
  // Prepares for queries against the live faces of `a` around interior point
  // `c`; `round` maps space so that the hull looks round (rounding_map
  // above; any invertible matrix will do: it only shapes the cells and the
  // ellipsoid). Returns false when c is not strictly behind every live face.
  // The adapter is copied (it is a view: a pointer to the faces).
  // `queries` (how many points will be asked about) sizes the optional
  // work: the faces' adjacency is cached when there are at least 4 points a
  // face, and with `cell_bounds` each cell of the cube map carries a
  // certified inner radius (see build_cell_radii) when faces x cells is at
  // most 2 queries; only for callers that ignore distances below a few eps,
  // since a point within rounding of the surface may then be reported inside.
  bool prepare(const A& a, const Eigen::Vector3d& c, const Eigen::Matrix3d& round, std::size_t queries = 0,
               bool cell_bounds = false) {
    a_ = a;
    c_ = c;
    to_round_ = round;
    from_round_ = round.inverse();
    if (!from_round_.allFinite()) to_round_ = from_round_ = Eigen::Matrix3d::Identity();
    const std::size_t nf = a.face_count();
    height_.assign(nf, 0.0);
    cache_adjacency_ = 4 * nf <= queries;
    if (cache_adjacency_) adjacent_span_.assign(nf, {0, kInvalidIndex});
    adjacent_.clear();
    inner_ = ball_ = std::numeric_limits<double>::infinity();
    Index any = kInvalidIndex;
    for (Index f = 0; f < nf; ++f) {
      if (!a.live(f)) continue;
      const double height = height_[f] = a.offset(f) - a.normal(f).dot(c);
      if (!(height > 0)) return false;
      // The ellipsoid |to_round_ x| < r lies behind this face when
      // r |to_round_^-T n| < h.
      inner_ = std::min(inner_, height / (from_round_.transpose() * a.normal(f)).norm());
      ball_ = std::min(ball_, height);
      any = f;
    }
    if (any == kInvalidIndex) return false;
    // Both shrunk by a millionth: a point where they touch a face is on the
    // surface, and rounding must not decide it is inside.
    inner_ *= 1 - 1e-6;
    inner_squared_ = inner_ * inner_;
    ball_ *= 1 - 1e-6;
    ball_squared_ = ball_ * ball_;
    any_ = any;
    cell_face_.clear();  // built on the first point outside the inner ellipsoid
    cell_radius_.clear();
    cell_bound_pairs_ = cell_bounds ? 2 * queries : 0;
    stamp_.assign(nf, 0);
    round_ = 0;
    return true;
  }

  // The face p is farthest in front of and that distance, or {kInvalidIndex,
  // 0} when p is behind (or on) every face.
  std::pair<Index, double> farthest_face_in_front(const Eigen::Vector3d& p) {
    const Eigen::Vector3d rel = p - c_;
    if (rel.squaredNorm() < ball_squared_) return {kInvalidIndex, 0.0};  // in the ball around c: cheaper
    const Eigen::Vector3d round_rel = to_round_ * rel;
    if (round_rel.squaredNorm() < inner_squared_) return {kInvalidIndex, 0.0};
    if (cell_face_.empty()) build_cube_map();
    const std::size_t cell = cell_of(round_rel);
    if (!cell_radius_.empty()) {
      // round_rel is the round image of a point within margin_per_rel_
      // |rel|_1 (round units) of p's: p is inside when that ball is inside
      // the cell's radius (its direction within the slack the cells carry).
      const double rel1 = rel.cwiseAbs().sum();
      const double t = cell_radius_[cell] - margin_per_rel_ * rel1;
      if (rel1 <= rel_cap_ && t > 0 && round_rel.squaredNorm() < t * t) return {kInvalidIndex, 0.0};
    }
    Index face = climb(cell_face_[cell], rel);
    double best_d = distance(face, p);
    if (!(best_d > 0)) {
      // The exit face comes from a ratio whose denominator h_f is tiny for
      // the faces of a thin hull (c lies within ~1e-10 of them): rounding can
      // then pick a neighbour of the true exit face, one the ray grazes and p
      // is behind, while p is outside the true one (e.g. a
      // wedge 7e-10 thick, a point 1.3e-8 outside its end face reported as
      // inside). The true exit face is across an edge of the chosen one, so
      // its ring decides.
      const Index exit = face;
      const double behind = -best_d;
      const auto consider = [&](Index nb) {
        const double d = distance(nb, p);
        if (d > best_d) best_d = d, face = nb;
      };
      for_each_neighbor(exit, consider);
      // Where the ray passes within rounding of a vertex, the faces around
      // it tie, and the one chosen may share only that vertex with the face
      // p is outside of (e.g. near-duplicates on a ray 1.5e6
      // from the origin, 2.5e-8 outside a face through the outermost one).
      // Missing that face needs the ratios of the two faces to agree within
      // their rounding, which bounds how far p can be behind the chosen one:
      // within that reach (generously, 1024 ulps of the coordinates), the
      // faces around the chosen face's corners decide. Points deeper inside
      // pay nothing more.
      const double reach = 1024 * std::numeric_limits<double>::epsilon() *
                           (p.cwiseAbs().sum() + c_.cwiseAbs().sum() + std::abs(a_.offset(exit)) + height_[exit]);
      if (!(best_d > 0) && behind <= reach) a_.for_each_corner_face(exit, consider);
      if (!(best_d > 0)) return {kInvalidIndex, 0.0};
    }
    Index best = face;
    if (++round_ == 0) std::fill(stamp_.begin(), stamp_.end(), 0), round_ = 1;
    stack_.assign(1, face);
    stamp_[face] = round_;
    for (std::size_t guard = 0; !stack_.empty() && guard <= height_.size(); ++guard) {
      const Index f = stack_.back();
      stack_.pop_back();
      for_each_neighbor(f, [&](Index nb) {
        if (stamp_[nb] == round_) return;
        stamp_[nb] = round_;
        const double d = distance(nb, p);
        if (d > 0) {
          stack_.push_back(nb);
          if (d > best_d) best_d = d, best = nb;
        }
      });
    }
    return {best, best_d};
  }

 private:
  void build_cube_map() {
    std::size_t live = 0;
    for (Index f = 0; f < height_.size(); ++f) live += a_.live(f);
    // About one face a cell: each climb then takes a step or two, and the
    // map costs a fraction of the faces' count to build.
    k_ = static_cast<int>(std::clamp(std::sqrt(static_cast<double>(live) / 6.0), 1.0, 64.0));
    cell_face_.resize(static_cast<std::size_t>(6 * k_ * k_));
    Index face = any_;
    for (int side = 0; side < 6; ++side)
      for (int iu = 0; iu < k_; ++iu)
        for (int iv = 0; iv < k_; ++iv) {
          Eigen::Vector3d d;
          const int axis = side / 2;
          d[axis] = side % 2 ? 1.0 : -1.0;
          d[(axis + 1) % 3] = (iu + 0.5) / k_ * 2 - 1;
          d[(axis + 2) % 3] = (iv + 0.5) / k_ * 2 - 1;
          face = climb(face, from_round_ * d);
          cell_face_[static_cast<std::size_t>((side * k_ + iu) * k_ + iv)] = face;
        }
    if (cell_bound_pairs_ > 0 && live * cell_face_.size() <= cell_bound_pairs_) build_cell_radii();
  }

  // A lower bound, per cell, of how far the hull's surface is from c along
  // any direction of the cell (round coordinates): a cell lies in the cap of
  // half-angle alpha around its centre direction a, and along a direction u
  // of the cap the plane of face f is at rho_f / (n_f . u) (rho_f its
  // distance from c, n_f its unit normal, both round), at least
  // rho_f / cos(max(0, theta_f - alpha)) with theta_f the angle of n_f from
  // a. Points inside that radius need no climb: a thin hull's cells (a slab
  // is a cube in round coordinates) are inside far beyond the inscribed
  // ellipsoid. The cap is widened by kSlack, which covers the rounding of a
  // point's round image (below rel_cap_), and the radius shrunk by 1e-5 for
  // the rounding of the round map and its inverse (relative 1e-7 on a slab
  // 1e-9 thick: the round normal of a face along the thin axis cancels).
  void build_cell_radii() {
    constexpr double kSlack = 1e-3;
    margin_per_rel_ = 32 * std::numeric_limits<double>::epsilon() * to_round_.cwiseAbs().rowwise().sum().maxCoeff();
    rel_cap_ = kSlack * inner_ / margin_per_rel_;
    if (!(rel_cap_ > 0) || !std::isfinite(margin_per_rel_)) return;
    struct RoundFace {
      Eigen::Vector3d unit;
      double rho;
    };
    std::vector<RoundFace> round_faces;
    for (Index f = 0; f < height_.size(); ++f) {
      if (!a_.live(f)) continue;
      const Eigen::Vector3d n = from_round_.transpose() * a_.normal(f);
      const double length = n.norm();
      if (!(length > 0) || !std::isfinite(length)) return;
      round_faces.push_back({n / length, height_[f] / length});
    }
    cell_radius_.assign(cell_face_.size(), 0.0);
    for (int side = 0; side < 6; ++side)
      for (int iu = 0; iu < k_; ++iu)
        for (int iv = 0; iv < k_; ++iv) {
          const int axis = side / 2;
          auto direction = [&](double u, double v) {
            Eigen::Vector3d d;
            d[axis] = side % 2 ? 1.0 : -1.0;
            d[(axis + 1) % 3] = u / k_ * 2 - 1;
            d[(axis + 2) % 3] = v / k_ * 2 - 1;
            return Eigen::Vector3d(d.normalized());
          };
          const Eigen::Vector3d centre = direction(iu + 0.5, iv + 0.5);
          double cos_half = 1;
          for (int corner = 0; corner < 4; ++corner)
            cos_half = std::min(cos_half, centre.dot(direction(iu + corner % 2, iv + corner / 2)));
          const double alpha = std::acos(std::clamp(cos_half, -1.0, 1.0)) + 1.01 * kSlack + 1e-9;
          if (!(alpha < 1.5)) continue;  // radius 0: no shortcut
          const double ca = std::cos(alpha), sa = std::sin(alpha);
          double radius = std::numeric_limits<double>::infinity();
          for (const RoundFace& rf : round_faces) {
            const double ct = rf.unit.dot(centre);
            const double reach = ct >= ca ? 1.0 : ct * ca + std::sqrt(std::max(0.0, 1 - ct * ct)) * sa;
            if (reach > 0) radius = std::min(radius, rf.rho / reach);
          }
          if (std::isfinite(radius))
            cell_radius_[static_cast<std::size_t>((side * k_ + iu) * k_ + iv)] = radius * (1 - 1e-5);
        }
  }

  double distance(Index f, const Eigen::Vector3d& p) const { return a_.normal(f).dot(p) - a_.offset(f); }

  // The faces across f's edges, in the adapter's order (when cached,
  // gathered on the first visit: a climb visits few of a hull's faces).
  template <class Fn>
  void for_each_neighbor(Index f, Fn&& fn) const {
    if (!cache_adjacency_) {
      a_.for_each_neighbor(f, fn);
      return;
    }
    std::pair<Index, Index>& span = adjacent_span_[f];
    if (span.second == kInvalidIndex) {  // first visit: gather them
      span.first = static_cast<Index>(adjacent_.size());
      a_.for_each_neighbor(f, [&](Index nb) { adjacent_.push_back(nb); });
      span.second = static_cast<Index>(adjacent_.size()) - span.first;
    }
    const Index* it = adjacent_.data() + span.first;
    const Index* end = it + span.second;
    for (; it != end; ++it) fn(*it);
  }

  Index climb(Index face, const Eigen::Vector3d& dir) const {
    auto g = [&](Index f) { return a_.normal(f).dot(dir) / height_[f]; };
    double gf = g(face);
    for (std::size_t step = 0; step <= height_.size(); ++step) {
      Index best = face;
      double best_g = gf;
      for_each_neighbor(face, [&](Index nb) {
        const double gn = g(nb);
        if (gn > best_g) best_g = gn, best = nb;
      });
      if (best == face) break;
      face = best, gf = best_g;
    }
    return face;
  }

  std::size_t cell_of(const Eigen::Vector3d& d) const {
    int axis = 0;
    d.cwiseAbs().maxCoeff(&axis);
    const double m = std::abs(d[axis]);
    if (!(m > 0)) return 0;
    const int side = 2 * axis + (d[axis] > 0 ? 1 : 0);
    const double u = d[(axis + 1) % 3] / m, v = d[(axis + 2) % 3] / m;  // in [-1, 1]
    const int iu = std::clamp(static_cast<int>((u + 1) * 0.5 * k_), 0, k_ - 1);
    const int iv = std::clamp(static_cast<int>((v + 1) * 0.5 * k_), 0, k_ - 1);
    return static_cast<std::size_t>((side * k_ + iu) * k_ + iv);
  }

  A a_{};
  Eigen::Vector3d c_ = Eigen::Vector3d::Zero();
  Eigen::Matrix3d to_round_ = Eigen::Matrix3d::Identity(), from_round_ = Eigen::Matrix3d::Identity();
  // A live face's height above c (dead faces' entries unused), and when
  // cached the faces across its edges:
  // adjacent_span_[f] = (start in adjacent_, count), count kInvalidIndex
  // until the face is first visited.
  std::vector<double> height_;
  bool cache_adjacency_ = false;
  mutable std::vector<std::pair<Index, Index>> adjacent_span_;
  mutable std::vector<Index> adjacent_;
  double inner_ = 0, inner_squared_ = 0;  // the ellipsoid's radius in round coordinates
  double ball_ = 0, ball_squared_ = 0;    // the inscribed ball's around c
  int k_ = 1;
  Index any_ = kInvalidIndex;
  std::vector<Index> cell_face_;
  std::vector<double> cell_radius_;  // per cell (build_cell_radii), or empty
  std::size_t cell_bound_pairs_ = 0;
  double margin_per_rel_ = 0, rel_cap_ = 0;
  std::vector<Index> stamp_, stack_;
  Index round_ = 0;
};

}  // namespace hedra::hull::detail
