// SAT between convex polyhedra (see sat.hpp for the algorithm and frames).
#include <cmath>
#include <hedra/collision/detail/sat.hpp>
#include <hedra/hull/assert.hpp>
#include <vector>

namespace hedra::collision {

const hull::HalfEdgeMesh& unit_box_mesh() {
  static const hull::HalfEdgeMesh mesh = [] {
    std::vector<Eigen::Vector3d> positions(8);
    for (int i = 0; i < 8; ++i) positions[i] = {i & 1 ? 1.0 : -1.0, i & 2 ? 1.0 : -1.0, i & 4 ? 1.0 : -1.0};
    // Counter-clockwise seen from outside: -x, +x, -y, +y, -z, +z.
    const std::vector<std::vector<hull::Index>> polygons = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4},
                                                            {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
    hull::HalfEdgeMesh m;
    hull::HalfEdgeMesh::from_polygons(positions, polygons, m);
    return m;
  }();
  return mesh;
}

SatPolytope sat_polytope(const Box& box, BoxPolytopeStorage& storage) {
  const hull::HalfEdgeMesh& mesh = unit_box_mesh();
  const Eigen::Vector3d& h = box.half_extents;
  for (int i = 0; i < 8; ++i) storage.vertices[i] = mesh.position(static_cast<hull::Index>(i)).cwiseProduct(h);
  for (int f = 0; f < 6; ++f) {
    const Eigen::Vector3d& n = mesh.plane(static_cast<hull::Index>(f)).normal;
    storage.planes[f] = {n, n.cwiseAbs().dot(h)};
  }
  SatPolytope p;
  p.mesh = &mesh;
  p.vertices = storage.vertices.data();
  p.planes = storage.planes.data();
  p.scale = h.norm();
  p.half_extents = h;
  return p;
}

SatPolytope sat_polytope(const ConvexPolyhedron& poly) {
  SatPolytope p;
  p.mesh = &poly.mesh();
  p.vertices = poly.vertices().data();
  p.poly = &poly;
  p.scale = poly.bounding_radius();
  return p;
}

namespace {

// Face f of A against B: B's deepest vertex below f's plane.
SatAxis face_of_a(const SatPolytope& a, const SatPolytope& b, const RelativePose& rel, hull::Index f) {
  const hull::Plane& plane = a.plane(f);
  const hull::Index v = b.support(-(rel.rotation.transpose() * plane.normal));
  SatAxis axis;
  axis.kind = SatAxisKind::face_a;
  axis.feature_a = f;
  axis.separation = plane.normal.dot(rel.rotation * b.vertex(v) + rel.translation) - plane.offset;
  axis.normal = plane.normal;
  return axis;
}

// Face f of B against A, in B's frame: A's vertex x maps to R^T (x - t).
SatAxis face_of_b(const SatPolytope& a, const SatPolytope& b, const RelativePose& rel, hull::Index f) {
  const hull::Plane& plane = b.plane(f);
  const Eigen::Vector3d n_in_a = rel.rotation * plane.normal;
  const hull::Index v = a.support(-n_in_a);
  SatAxis axis;
  axis.kind = SatAxisKind::face_b;
  axis.feature_b = f;
  axis.separation = plane.normal.dot(rel.rotation.transpose() * (a.vertex(v) - rel.translation)) - plane.offset;
  axis.normal = -n_in_a;
  return axis;
}

// The half-edge of the unit box running from vertex v0 to vertex v1.
hull::Index box_half_edge(hull::Index v0, hull::Index v1) {
  const hull::HalfEdgeMesh& m = unit_box_mesh();
  for (hull::Index e = 0; e < m.half_edge_count(); ++e)
    if (m.origin(e) == v0 && m.destination(e) == v1) return e;
  return hull::kInvalidIndex;  // unreachable: v0, v1 differ in one bit
}

// Box-box edge axes (see sat.hpp). A's axes are the unit vectors, B's the
// columns of R; N = e_i x f_j turned toward B's centre.
void box_edge_query(const SatPolytope& a, const SatPolytope& b, const RelativePose& rel, const SatSettings& settings,
                    SatResult& out) {
  const Eigen::Matrix3d& r = rel.rotation;
  const Eigen::Vector3d& ha = a.half_extents;
  const Eigen::Vector3d& hb = b.half_extents;
  int best_i = -1, best_j = -1;
  // With n = e_i x f_j (unnormalised, |n| = sqrt(1 - R_ij^2)) and (i1, i2),
  // (j1, j2) the other two indices in cyclic order (Gottschalk's OBB test):
  //   n . t      = t_i2 R_i1j - t_i1 R_i2j
  //   radius_a   = ha_i1 |R_i2j| + ha_i2 |R_i1j|
  //   radius_b   = hb_j1 |R_ij2| + hb_j2 |R_ij1|
  const Eigen::Vector3d& t = rel.translation;
  for (int i = 0; i < 3; ++i) {
    const int i1 = (i + 1) % 3, i2 = (i + 2) % 3;
    for (int j = 0; j < 3; ++j) {
      const int j1 = (j + 1) % 3, j2 = (j + 2) % 3;
      const double len2 = 1.0 - r(i, j) * r(i, j);
      if (!(len2 > settings.parallel_tolerance * settings.parallel_tolerance)) continue;
      const double nt = t[i2] * r(i1, j) - t[i1] * r(i2, j);
      const double radius_a = ha[i1] * std::abs(r(i2, j)) + ha[i2] * std::abs(r(i1, j));
      const double radius_b = hb[j1] * std::abs(r(i, j2)) + hb[j2] * std::abs(r(i, j1));
      const double s = (std::abs(nt) - radius_a - radius_b) / std::sqrt(len2);
      ++out.edge_pairs;
      if (s > out.edge.separation) {
        Eigen::Vector3d n = Eigen::Vector3d::Unit(i).cross(r.col(j)).normalized();
        if (nt < 0.0) n = -n;
        out.edge.separation = s;
        out.edge.normal = n;
        best_i = i;
        best_j = j;
      }
    }
  }
  if (best_i < 0) return;
  out.edge.kind = SatAxisKind::edge;
  // A's support edge along n: the vertices with the signs of n off axis i.
  const Eigen::Vector3d& n = out.edge.normal;
  const hull::Index va = a.support(n) & ~(1u << best_i);
  const Eigen::Vector3d nb = -(r.transpose() * n);
  const hull::Index vb = b.support(nb) & ~(1u << best_j);
  out.edge.feature_a = box_half_edge(va, va | (1u << best_i));
  out.edge.feature_b = box_half_edge(vb, vb | (1u << best_j));
  if (out.edge.separation > settings.early_out) out.separated = true;
}

// Box-box face axes in closed form: A's face k facing B separates by
// |t_k| - h_k - (B's radius along e_k); B's face j facing A likewise. Face
// indices follow unit_box_mesh(): 2k for -axis k, 2k + 1 for +axis k.
void box_face_query(const SatPolytope& a, const SatPolytope& b, const RelativePose& rel, SatResult& out) {
  const Eigen::Matrix3d abs_r = rel.rotation.cwiseAbs();
  const Eigen::Vector3d& t = rel.translation;
  const Eigen::Vector3d t_in_b = rel.rotation.transpose() * t;
  const Eigen::Vector3d radius_b = abs_r * b.half_extents;              // B along A's axes
  const Eigen::Vector3d radius_a = abs_r.transpose() * a.half_extents;  // A along B's axes
  for (int k = 0; k < 3; ++k) {
    const double s = std::abs(t[k]) - a.half_extents[k] - radius_b[k];
    if (s > out.face_a.separation) {
      const bool plus = t[k] >= 0.0;
      out.face_a.kind = SatAxisKind::face_a;
      out.face_a.separation = s;
      out.face_a.feature_a = static_cast<hull::Index>(2 * k + (plus ? 1 : 0));
      out.face_a.normal = (plus ? 1.0 : -1.0) * Eigen::Vector3d::Unit(k);
    }
  }
  for (int j = 0; j < 3; ++j) {
    const double s = std::abs(t_in_b[j]) - b.half_extents[j] - radius_a[j];
    if (s > out.face_b.separation) {
      const bool plus = -t_in_b[j] >= 0.0;  // B's face toward A (direction -t)
      out.face_b.kind = SatAxisKind::face_b;
      out.face_b.separation = s;
      out.face_b.feature_b = static_cast<hull::Index>(2 * j + (plus ? 1 : 0));
      out.face_b.normal = -(plus ? 1.0 : -1.0) * rel.rotation.col(j);
    }
  }
}

}  // namespace

SatAxis sat_face_axis(const SatPolytope& a, const SatPolytope& b, const RelativePose& b_in_a, bool of_a,
                      hull::Index face) {
  return of_a ? face_of_a(a, b, b_in_a, face) : face_of_b(a, b, b_in_a, face);
}

namespace {

// Faces of A, then faces of B; true when one separates beyond early_out.
bool hull_face_query(const SatPolytope& a, const SatPolytope& b, const RelativePose& rel, const SatSettings& settings,
                     SatResult& out) {
  for (hull::Index f = 0; f < a.mesh->face_count(); ++f) {
    const SatAxis axis = face_of_a(a, b, rel, f);
    if (axis.separation > out.face_a.separation) out.face_a = axis;
    if (axis.separation > settings.early_out) {
      out.separated = true;
      return true;
    }
  }
  for (hull::Index f = 0; f < b.mesh->face_count(); ++f) {
    const SatAxis axis = face_of_b(a, b, rel, f);
    if (axis.separation > out.face_b.separation) out.face_b = axis;
    if (axis.separation > settings.early_out) {
      out.separated = true;
      return true;
    }
  }
  return false;
}

// Edge pairs whose Gauss-map arcs cross (see sat.hpp); stops at the first
// pair that separates beyond early_out.
void hull_edge_query(const SatPolytope& a, const SatPolytope& b, const RelativePose& rel, const SatSettings& settings,
                     SatResult& out) {
  const hull::HalfEdgeMesh& ma = *a.mesh;
  const hull::HalfEdgeMesh& mb = *b.mesh;
  // Edge pairs whose Gauss-map arcs cross. Outer loop over B so that B's
  // data is rotated into A's frame once per edge of B. A's edge vectors are
  // gathered once into flat arrays on the stack (up to kEdgeCache edges,
  // ~14 kB) so the inner loop's first test streams through memory instead
  // of chasing half-edge links; larger hulls walk the mesh directly.
  constexpr std::size_t kEdgeCache = 512;
  double ex[kEdgeCache], ey[kEdgeCache], ez[kEdgeCache];
  hull::Index edge_index[kEdgeCache];
  std::size_t edge_count = 0;
  const std::size_t half_edges_a = ma.half_edge_count();
  const std::size_t half_edges_b = mb.half_edge_count();
  const bool gathered = ma.edge_count() <= kEdgeCache;
  if (gathered)
    for (hull::Index ea = 0; ea < half_edges_a; ++ea) {
      const hull::Index ta = ma.twin(ea);
      if (ta < ea) continue;
      const Eigen::Vector3d e_a = a.vertex(ma.origin(ta)) - a.vertex(ma.origin(ea));
      ex[edge_count] = e_a.x();
      ey[edge_count] = e_a.y();
      ez[edge_count] = e_a.z();
      edge_index[edge_count++] = ea;
    }
  const double tol2 = settings.parallel_tolerance * settings.parallel_tolerance;
  for (hull::Index eb = 0; eb < half_edges_b; ++eb) {
    const hull::Index tb = mb.twin(eb);
    if (tb < eb) continue;  // each edge once
    // c, d: B's face normals negated (the Gauss map of -B), A's frame.
    const Eigen::Vector3d c = -(rel.rotation * b.plane(mb.left_face(eb)).normal);
    const Eigen::Vector3d d = -(rel.rotation * b.plane(mb.left_face(tb)).normal);
    const Eigen::Vector3d pb = rel.rotation * b.vertex(mb.origin(eb)) + rel.translation;
    const Eigen::Vector3d e_b = rel.rotation * (b.vertex(mb.origin(tb)) - b.vertex(mb.origin(eb)));
    // d x c = (-n_right) x (-n_left) = n_right x n_left, antiparallel to e_b.
    const Eigen::Vector3d dxc = -e_b;
    const double e_b2 = e_b.squaredNorm();
    // The rest of the test for a pair whose first condition held
    // (cba = c . (b x a), dba = d . (b x a) of opposite signs); true when the
    // pair separates beyond early_out.
    const auto test_pair = [&](hull::Index ea, const Eigen::Vector3d& e_a, double cba) {
      const hull::Index ta = ma.twin(ea);
      const Eigen::Vector3d& na = a.plane(ma.left_face(ea)).normal;
      const Eigen::Vector3d& nb = a.plane(ma.left_face(ta)).normal;
      const double adc = na.dot(dxc), bdc = nb.dot(dxc);
      if (!(adc * bdc < 0.0) || !(cba * bdc > 0.0)) return false;
      ++out.edge_pairs;
      Eigen::Vector3d n = e_a.cross(e_b);
      const double len2 = n.squaredNorm();
      if (!(len2 > tol2 * e_a.squaredNorm() * e_b2)) return false;  // nearly parallel (or NaN)
      n /= std::sqrt(len2);
      const Eigen::Vector3d& pa = a.vertex(ma.origin(ea));
      // Oriented as the point where the two Gauss-map arcs cross: it lies on
      // A's arc (na, nb) and on -B's arc (c, d) with non-negative weights,
      // so its dot with na + nb + c + d is positive. Not "away from A's
      // centroid": an edge through the centroid (a box with zero extents,
      // a flat hull) leaves that sign to rounding. Both arcs half circles
      // (two flat shapes: the sum is rounding noise of unit normals,
      // ~1e-16, far below 1e-6): the centroid rule.
      const Eigen::Vector3d chords = na + nb + c + d;
      const bool by_arcs = chords.squaredNorm() > 1e-12;
      if ((by_arcs ? n.dot(chords) : n.dot(pa)) < 0.0) n = -n;
      const double s = n.dot(pb - pa);
      if (s > out.edge.separation) {
        out.edge.kind = SatAxisKind::edge;
        out.edge.separation = s;
        out.edge.feature_a = ea;
        out.edge.feature_b = eb;
        out.edge.normal = n;
        if (s > settings.early_out) {
          out.separated = true;
          return true;
        }
      }
      return false;
    };
    if (gathered) {
      for (std::size_t k = 0; k < edge_count; ++k) {
        // b x a = n_right x n_left of A's edge, antiparallel to e_a.
        const double cba = -(c.x() * ex[k] + c.y() * ey[k] + c.z() * ez[k]);
        const double dba = -(d.x() * ex[k] + d.y() * ey[k] + d.z() * ez[k]);
        if (!(cba * dba < 0.0)) continue;
        if (test_pair(edge_index[k], Eigen::Vector3d(ex[k], ey[k], ez[k]), cba)) return;
      }
    } else {
      for (hull::Index ea = 0; ea < half_edges_a; ++ea) {
        const hull::Index ta = ma.twin(ea);
        if (ta < ea) continue;
        const Eigen::Vector3d e_a = a.vertex(ma.origin(ta)) - a.vertex(ma.origin(ea));
        const double cba = -c.dot(e_a), dba = -d.dot(e_a);
        if (!(cba * dba < 0.0)) continue;
        if (test_pair(ea, e_a, cba)) return;
      }
    }
  }
}

// The full test (sat.hpp's sat_query).
SatResult sat_query_unchecked(const SatPolytope& a, const SatPolytope& b, const RelativePose& rel,
                              const SatSettings& settings) {
  SatResult out;
  if (!a.poly && !b.poly) {  // two boxes: closed forms
    box_face_query(a, b, rel, out);
    if (out.face_a.separation > settings.early_out || out.face_b.separation > settings.early_out) {
      out.separated = true;
      return out;
    }
    box_edge_query(a, b, rel, settings, out);
    return out;
  }
  if (hull_face_query(a, b, rel, settings, out)) return out;
  hull_edge_query(a, b, rel, settings, out);
  return out;
}

// What sat.hpp promises of an axis: none, or a unit normal (to the rotation
// tolerance B's placement is held to) with a separation that is not NaN
// and features that name it.
[[maybe_unused]] bool well_formed(const SatAxis& axis) {
  if (axis.kind == SatAxisKind::none) return true;
  const bool features = (axis.kind == SatAxisKind::face_a && axis.feature_a != hull::kInvalidIndex) ||
                        (axis.kind == SatAxisKind::face_b && axis.feature_b != hull::kInvalidIndex) ||
                        (axis.kind == SatAxisKind::edge && axis.feature_a != hull::kInvalidIndex &&
                         axis.feature_b != hull::kInvalidIndex);
  return features && !std::isnan(axis.separation) &&
         std::abs(axis.normal.squaredNorm() - 1.0) <= 8.0 * rotation_tolerance;
}

}  // namespace

SatResult sat_query(const SatPolytope& a, const SatPolytope& b, const RelativePose& rel, const SatSettings& settings) {
  SatResult out = sat_query_unchecked(a, b, rel, settings);
  HEDRA_ASSERT(well_formed(out.face_a) && well_formed(out.face_b) && well_formed(out.edge) && out.edge_pairs >= 0);
  return out;
}

}  // namespace hedra::collision
