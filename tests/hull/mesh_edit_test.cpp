// Tests of the editing operations: split_edge and split_face on several
// meshes (counts, degrees, planes, rejected requests), cut_by_plane on the
// cube through every kind of feature (vertex, edge, face, a plane barely
// touching a corner) with hand-computed counts and volumes, flat polygons,
// segments and points, and fixed-seed property tests over hundreds of random
// and feature-aligned planes through random convex solids: both halves
// validate, their volumes add up to the original and their caps agree.
// clip_polygon is checked on squares and against cut_by_plane on random flat
// polygons.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cstdio>
#include <hedra/hull/mass.hpp>
#include <hedra/hull/mesh_edit.hpp>
#include <limits>
#include <random>
#include <vector>

#include "test_meshes.hpp"

namespace hedra::hull {
namespace {

using Eigen::Vector3d;

Index find_edge(const HalfEdgeMesh& m, Index a, Index b) {
  for (Index e = 0; e < m.edges.size(); ++e)
    if (m.edges[e].origin == a && m.edges[m.edges[e].twin].origin == b) return e;
  return kInvalidIndex;
}

bool has_error(const ValidationReport& r, const std::string& what) {
  for (const auto& e : r.errors)
    if (e.find(what) != std::string::npos) return true;
  return false;
}

Plane make_plane(const Vector3d& normal, double offset) {
  Plane p;
  p.normal = normal;
  p.offset = offset;
  return p;
}

Plane flipped(const Plane& p) { return make_plane(-p.normal, -p.offset); }

double polygon_area(const Vector3d* p, std::size_t n) {
  Vector3d s = Vector3d::Zero();
  for (std::size_t i = 1; i + 1 < n; ++i) s += (p[i] - p[0]).cross(p[i + 1] - p[0]);
  return 0.5 * s.norm();
}

double face_area(const HalfEdgeMesh& m, Index f) {
  std::vector<Vector3d> pts;
  for (Index v : m.face_vertices(f)) pts.push_back(m.position(v));
  return polygon_area(pts.data(), pts.size());
}

// Full-precision description of a plane, for replaying a failure.
std::string describe(const Plane& p) {
  char buf[160];
  std::snprintf(buf, sizeof buf, "plane n=(%.17g, %.17g, %.17g) d=%.17g", p.normal.x(), p.normal.y(), p.normal.z(),
                p.offset);
  return buf;
}

// ---- split_edge --------------------------------------------------------------

TEST(SplitEdge, EveryCubeEdgeAtItsMidpoint) {
  const HalfEdgeMesh cube = test::unit_cube();
  for (Index e = 0; e < cube.edges.size(); ++e) {
    HalfEdgeMesh m = cube;
    const Index a = m.origin(e), b = m.destination(e), f = m.left_face(e), g = m.right_face(e);
    const Vector3d mid = 0.5 * (m.position(a) + m.position(b));
    const Index v = split_edge(m, e, mid);
    ASSERT_EQ(v, 8u);
    EXPECT_TRUE(m.validate().ok()) << m.validate().to_string();
    EXPECT_EQ(m.vertex_count(), 9u);
    EXPECT_EQ(m.edge_count(), 13u);
    EXPECT_EQ(m.face_count(), 6u);
    EXPECT_EQ(m.position(v), mid);
    EXPECT_EQ(m.vertex_degree(v), 2u);
    EXPECT_EQ(m.face_degree(f), 5u);
    EXPECT_EQ(m.face_degree(g), 5u);
    EXPECT_NE(find_edge(m, a, v), kInvalidIndex);
    EXPECT_NE(find_edge(m, v, b), kInvalidIndex);
    EXPECT_EQ(find_edge(m, a, b), kInvalidIndex);
    for (Index k = 0; k < 6; ++k) {
      EXPECT_EQ(m.plane(k).normal, cube.plane(k).normal);
      EXPECT_EQ(m.plane(k).offset, cube.plane(k).offset);
    }
  }
}

TEST(SplitEdge, AllEdgesInTurnThenAgain) {
  HalfEdgeMesh m = test::make_prism(test::regular_polygon(5, 1.0), 0, 2);
  const std::size_t edges = m.edge_count(), verts = m.vertex_count();
  std::vector<Index> one_per_edge;
  for (Index e = 0; e < m.edges.size(); ++e)
    if (e < m.twin(e)) one_per_edge.push_back(e);
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0.05, 0.95);
  for (Index e : one_per_edge) {
    const double t = u(rng);
    ASSERT_NE(split_edge(m, e, (1 - t) * m.position(m.origin(e)) + t * m.position(m.destination(e))), kInvalidIndex);
  }
  EXPECT_TRUE(m.validate().ok()) << m.validate().to_string();
  EXPECT_EQ(m.vertex_count(), verts + edges);
  EXPECT_EQ(m.edge_count(), 2 * edges);
  // Split a piece of an already split edge (half-edge of the new second half).
  const Index e = static_cast<Index>(m.edges.size() - 1);
  ASSERT_NE(split_edge(m, e, 0.5 * (m.position(m.origin(e)) + m.position(m.destination(e)))), kInvalidIndex);
  EXPECT_TRUE(m.validate().ok()) << m.validate().to_string();
  EXPECT_NEAR(volume(m), 5 * 0.5 * std::sin(2 * M_PI / 5) * 2, 1e-12);
}

TEST(SplitEdge, FlatPolygonSplitsBothSides) {
  HalfEdgeMesh m = test::make_flat_polygon({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}});
  ASSERT_EQ(split_edge(m, find_edge(m, 1, 2), {1, 0.25, 0}), 4u);
  EXPECT_TRUE(m.validate().ok()) << m.validate().to_string();
  EXPECT_EQ(m.face_degree(0), 5u);
  EXPECT_EQ(m.face_degree(1), 5u);
}

TEST(SplitEdge, RejectsBadRequestsAndDocumentsOffSegmentPoints) {
  HalfEdgeMesh m = test::unit_cube();
  const auto before = m.polygons();
  EXPECT_EQ(split_edge(m, 24, {0.5, 0, 0}), kInvalidIndex);
  EXPECT_EQ(split_edge(m, 0, {std::nan(""), 0, 0}), kInvalidIndex);
  EXPECT_EQ(m.polygons(), before);
  EXPECT_EQ(m.vertex_count(), 8u);
  // Off the segment (outside the cube): the structure is sound but validate
  // names the geometry.
  const Index v = split_edge(m, find_edge(m, 0, 1), {0.5, -0.25, -0.25});
  ASSERT_NE(v, kInvalidIndex);
  const ValidationReport r = m.validate();
  EXPECT_TRUE(has_error(r, "off the face plane")) << r.to_string();
  EXPECT_FALSE(has_error(r, "twin(twin(e))"));
  EXPECT_FALSE(has_error(r, "next(prev(e))"));
  EXPECT_FALSE(has_error(r, "Euler"));
}

// ---- split_face --------------------------------------------------------------

TEST(SplitFace, BothDiagonalsOfEveryCubeFace) {
  const HalfEdgeMesh cube = test::unit_cube();
  const auto polys = test::box_polygons();
  for (Index f = 0; f < 6; ++f) {
    for (int k = 0; k < 2; ++k) {
      HalfEdgeMesh m = cube;
      const Index a = polys[f][k], b = polys[f][k + 2];
      const Index g = split_face(m, f, a, b);
      ASSERT_EQ(g, 6u);
      EXPECT_TRUE(m.validate().ok()) << m.validate().to_string();
      EXPECT_EQ(m.face_count(), 7u);
      EXPECT_EQ(m.edge_count(), 13u);
      EXPECT_EQ(m.face_degree(f), 3u);
      EXPECT_EQ(m.face_degree(g), 3u);
      // f keeps a, ..., b; g has b, ..., a; they share the diagonal.
      const Index d = find_edge(m, b, a);
      ASSERT_NE(d, kInvalidIndex);
      EXPECT_EQ(m.left_face(d), f);
      EXPECT_EQ(m.right_face(d), g);
      EXPECT_EQ(m.plane(g).normal, m.plane(f).normal);
      EXPECT_NEAR(face_area(m, f) + face_area(m, g), 1.0, 1e-15);
    }
  }
}

TEST(SplitFace, FanOfAnOctagon) {
  // Split the top octagon of a prism into a fan from vertex n: 6 splits.
  const int n = 8;
  HalfEdgeMesh m = test::make_prism(test::regular_polygon(n, 1.0), 0, 1);
  Index face = 1;  // top: n, n+1, ..., 2n-1
  for (int k = 2; k < n - 1; ++k) {
    const Index g = split_face(m, face, n, n + k);
    ASSERT_NE(g, kInvalidIndex) << k;
    EXPECT_TRUE(m.validate().ok()) << m.validate().to_string();
    EXPECT_EQ(m.face_degree(face), 3u);  // n, the previous fan corner, n + k
    face = g;
  }
  EXPECT_EQ(m.face_count(), 2u + n + (n - 3));
  EXPECT_EQ(m.face_degree(face), 3u);
}

TEST(SplitFace, RejectsBadRequests) {
  HalfEdgeMesh m = test::unit_cube();
  const auto before = m.polygons();
  EXPECT_EQ(split_face(m, kInvalidIndex, 4, 6), kInvalidIndex);  // no such face
  EXPECT_EQ(split_face(m, test::kTop, 4, 4), kInvalidIndex);     // same vertex
  EXPECT_EQ(split_face(m, test::kTop, 4, 5), kInvalidIndex);     // adjacent
  EXPECT_EQ(split_face(m, test::kTop, 7, 4), kInvalidIndex);     // adjacent (wrapping)
  EXPECT_EQ(split_face(m, test::kTop, 4, 2), kInvalidIndex);     // 2 is not on the top
  EXPECT_EQ(m.polygons(), before);
  // After a split of edge 4-5, vertices 4 and 5 are no longer adjacent on the
  // top, but the "diagonal" 4-5 would cut off a face without area.
  const Index mid = split_edge(m, find_edge(m, 4, 5), {0.5, 0, 1});
  ASSERT_NE(mid, kInvalidIndex);
  EXPECT_EQ(split_face(m, test::kTop, 4, 5), kInvalidIndex);
  // From the new vertex to the far corners is fine.
  EXPECT_NE(split_face(m, test::kTop, mid, 7), kInvalidIndex);
  EXPECT_NE(split_face(m, test::kTop, mid, 6), kInvalidIndex);
  EXPECT_TRUE(m.validate().ok()) << m.validate().to_string();
  EXPECT_EQ(m.face_count(), 8u);
}

// ---- cut_by_plane on the unit cube -------------------------------------------

struct CubeCut {
  const char* name;
  Vector3d normal;
  double offset;
  CutStatus status;
  std::size_t V, E, F;
  double volume;
};

TEST(CutByPlane, CubeThroughEveryKindOfFeature) {
  const CubeCut cases[] = {
      {"mid z", {0, 0, 1}, 0.5, CutStatus::cut, 8, 12, 6, 0.5},
      {"unnormalised mid z", {0, 0, 4}, 2.0, CutStatus::cut, 8, 12, 6, 0.5},
      {"through edge 4-7 and two crossings (x+2z=2)", {1, 0, 2}, 2.0, CutStatus::cut, 8, 12, 6, 0.75},
      {"through 4 vertices along 2 edges (x+y=1)", {1, 1, 0}, 1.0, CutStatus::cut, 6, 9, 5, 0.5},
      {"along edges 0-4 and 2-6 (x=y)", {1, -1, 0}, 0.0, CutStatus::cut, 6, 9, 5, 0.5},
      {"through 3 vertices (x+y+z=2)", {1, 1, 1}, 2.0, CutStatus::cut, 7, 12, 7, 1.0 - 1.0 / 6},
      {"corner (x+y+z=2.5)", {1, 1, 1}, 2.5, CutStatus::cut, 10, 15, 7, 1.0 - 1.0 / 48},
      {"hexagon (x+y+z=1.5)", {1, 1, 1}, 1.5, CutStatus::cut, 10, 15, 7, 0.5},
      {"touches corner 6", {1, 1, 1}, 3.0, CutStatus::unchanged, 8, 12, 6, 1.0},
      {"only corner 6 behind-or-on", {-1, -1, -1}, -3.0, CutStatus::emptied, 0, 0, 0, 0.0},
      {"touches edge 5-6", {1, 0, 1}, 2.0, CutStatus::unchanged, 8, 12, 6, 1.0},
      {"only edge 5-6 kept", {-1, 0, -1}, -2.0, CutStatus::emptied, 0, 0, 0, 0.0},
      {"coincides with the top", {0, 0, 1}, 1.0, CutStatus::unchanged, 8, 12, 6, 1.0},
      {"coincides with the top, reversed", {0, 0, -1}, -1.0, CutStatus::emptied, 0, 0, 0, 0.0},
      {"all behind", {0, 0, 1}, 5.0, CutStatus::unchanged, 8, 12, 6, 1.0},
      {"all in front", {0, 0, 1}, -5.0, CutStatus::emptied, 0, 0, 0, 0.0},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.name);
    HalfEdgeMesh m = test::unit_cube();
    const Plane plane = make_plane(c.normal, c.offset);
    const CutResult r = cut_by_plane(m, plane);
    EXPECT_EQ(r.status, c.status) << to_string(r.status);
    EXPECT_EQ(m.vertex_count(), c.V);
    EXPECT_EQ(m.edge_count(), c.E);
    EXPECT_EQ(m.face_count(), c.F);
    if (c.V > 0) {
      EXPECT_TRUE(m.validate().ok()) << m.validate().to_string();
      EXPECT_NEAR(volume(m), c.volume, 1e-14);
    }
    if (r.status == CutStatus::cut) {
      ASSERT_EQ(r.cap_face, m.face_count() - 1);
      const Vector3d n = c.normal.normalized();
      EXPECT_LT((m.plane(r.cap_face).normal - n).norm(), 1e-15);
      EXPECT_NEAR(m.plane(r.cap_face).offset, c.offset / c.normal.norm(), 1e-15);
      ASSERT_EQ(r.face_source.size(), m.face_count());
      EXPECT_EQ(r.face_source.back(), kInvalidIndex);
      const HalfEdgeMesh cube = test::unit_cube();
      for (Index f = 0; f + 1 < m.face_count(); ++f) {
        ASSERT_LT(r.face_source[f], 6u);
        EXPECT_EQ(m.plane(f).normal, cube.plane(r.face_source[f]).normal);
      }
      EXPECT_EQ(m.vertex_count(), 8 - r.removed_vertices + r.added_vertices);
      for (Index v : m.face_vertices(r.cap_face))
        EXPECT_LE(std::abs(plane.signed_distance(m.position(v)) / c.normal.norm()), m.tolerance());
    }
    if (r.status == CutStatus::emptied) {
      EXPECT_EQ(r.removed_vertices, 8u);
    }
  }
}

TEST(CutByPlane, BarelyTouchingACornerSnapsOrCutsCleanly) {
  const HalfEdgeMesh cube = test::unit_cube();
  const double tol = cube.tolerance();
  const Vector3d n = Vector3d(1, 1, 1).normalized();
  const double at_corner = n.dot(Vector3d(1, 1, 1));
  // Within tolerance of corner 6: the corner counts as on the plane.
  for (double k : {-0.9, -0.5, 0.0, 0.5, 0.9}) {
    HalfEdgeMesh m = cube;
    const CutResult r = cut_by_plane(m, make_plane(n, at_corner - k * tol));
    EXPECT_EQ(r.status, CutStatus::unchanged) << k;
    HalfEdgeMesh back = cube;
    EXPECT_EQ(cut_by_plane(back, make_plane(-n, -(at_corner - k * tol))).status, CutStatus::emptied) << k;
  }
  // Just beyond it: a tiny corner is cut off, with no vertex closer than
  // tolerance to another.
  for (double k : {1.5, 3.0, 10.0, 1e3}) {
    HalfEdgeMesh m = cube;
    const CutResult r = cut_by_plane(m, make_plane(n, at_corner - k * tol));
    ASSERT_EQ(r.status, CutStatus::cut) << k;
    EXPECT_TRUE(m.validate().ok()) << k << "\n" << m.validate().to_string();
    EXPECT_EQ(m.vertex_count(), 10u);
    EXPECT_EQ(m.face_degree(r.cap_face), 3u);
    for (Index a = 0; a < m.vertex_count(); ++a)
      for (Index b = a + 1; b < m.vertex_count(); ++b)
        EXPECT_GT((m.position(a) - m.position(b)).norm(), tol) << k << ": " << a << " " << b;
    // The removed tip is the flipped cut: a tetrahedron of legs k tol sqrt(3).
    HalfEdgeMesh tip = cube;
    ASSERT_EQ(cut_by_plane(tip, make_plane(-n, -(at_corner - k * tol))).status, CutStatus::cut);
    EXPECT_TRUE(tip.validate().ok()) << tip.validate().to_string();
    EXPECT_EQ(tip.vertex_count(), 4u);
    // Coordinates near 1 carry rounding of 1e-16 on legs of a few 1e-14, so
    // the tip's volume is only good to a few per cent.
    const double leg = k * tol * std::sqrt(3.0);
    EXPECT_NEAR(volume(tip), leg * leg * leg / 6, 0.05 * leg * leg * leg / 6);
  }
}

TEST(CutByPlane, ThinSlabOffAFace) {
  // A plane 2 tol inside the top face: the cap and a slab of thickness 2 tol.
  const HalfEdgeMesh box = test::make_box({-1, -2, -3}, {1, 2, 3});
  const double tol = box.tolerance();
  HalfEdgeMesh below = box, slab = box;
  const Plane p = make_plane({0, 0, 1}, 3 - 2 * tol);
  ASSERT_EQ(cut_by_plane(below, p).status, CutStatus::cut);
  ASSERT_EQ(cut_by_plane(slab, flipped(p)).status, CutStatus::cut);
  EXPECT_TRUE(below.validate().ok()) << below.validate().to_string();
  EXPECT_TRUE(slab.validate().ok()) << slab.validate().to_string();
  EXPECT_EQ(slab.vertex_count(), 8u);
  // z near 3 carries rounding of 4e-16 against a thickness of 6e-14.
  EXPECT_NEAR(volume(slab), 2 * 4 * 2 * tol, 0.05 * 16 * tol);
  EXPECT_NEAR(volume(slab) + volume(below), 48.0, 1e-13);
}

TEST(CutByPlane, FlatPolygon) {
  const HalfEdgeMesh square = test::make_flat_polygon({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}});
  {
    HalfEdgeMesh m = square;
    const CutResult r = cut_by_plane(m, make_plane({1, 0, 0}, 0.5));
    ASSERT_EQ(r.status, CutStatus::cut);
    EXPECT_EQ(r.cap_face, kInvalidIndex);  // cut across, no cap
    EXPECT_TRUE(m.validate().ok()) << m.validate().to_string();
    EXPECT_EQ(m.vertex_count(), 4u);
    EXPECT_EQ(m.face_count(), 2u);
    EXPECT_NEAR(face_area(m, 0), 0.5, 1e-15);
    EXPECT_NEAR(mass_properties(m).centroid.x(), 0.25, 1e-15);
  }
  {
    // Along the diagonal through vertices 0 and 2: a triangle, no new vertex.
    HalfEdgeMesh m = square;
    const CutResult r = cut_by_plane(m, make_plane({1, -1, 0}, 0.0));
    ASSERT_EQ(r.status, CutStatus::cut);
    EXPECT_EQ(r.added_vertices, 0u);
    EXPECT_TRUE(m.validate().ok()) << m.validate().to_string();
    EXPECT_EQ(m.vertex_count(), 3u);
    EXPECT_NEAR(face_area(m, 1), 0.5, 1e-15);
  }
  {
    HalfEdgeMesh m = square;  // the plane of the polygon itself
    EXPECT_EQ(cut_by_plane(m, make_plane({0, 0, 1}, 0)).status, CutStatus::unchanged);
    EXPECT_EQ(cut_by_plane(m, make_plane({0, 0, -1}, 0)).status, CutStatus::unchanged);
    EXPECT_EQ(cut_by_plane(m, make_plane({0, 1, 0}, 0)).status, CutStatus::emptied);  // only edge 0-1 kept
  }
}

TEST(CutByPlane, SegmentsAndPoints) {
  const double tol = 1e-14;
  HalfEdgeMesh seg = test::make_vertices_only({{0, 0, 0}, {2, 0, 0}}, tol);
  CutResult r = cut_by_plane(seg, make_plane({1, 0, 0}, 0.5));
  ASSERT_EQ(r.status, CutStatus::cut);
  ASSERT_EQ(seg.vertex_count(), 2u);
  EXPECT_EQ(seg.position(1), Vector3d(0.5, 0, 0));
  EXPECT_TRUE(seg.validate().ok());
  EXPECT_EQ(cut_by_plane(seg, make_plane({1, 0, 0}, 0.5)).status, CutStatus::unchanged);
  EXPECT_EQ(cut_by_plane(seg, make_plane({-1, 0, 0}, -0.5)).status, CutStatus::emptied);  // only the point 0.5
  EXPECT_EQ(seg.vertex_count(), 0u);

  HalfEdgeMesh pt = test::make_vertices_only({{1, 1, 1}}, tol);
  EXPECT_EQ(cut_by_plane(pt, make_plane({0, 1, 0}, 1)).status, CutStatus::unchanged);
  EXPECT_EQ(cut_by_plane(pt, make_plane({0, 1, 0}, 0.5)).status, CutStatus::emptied);
}

TEST(CutByPlane, RejectsBadPlanesAndMeshes) {
  HalfEdgeMesh m = test::unit_cube();
  const auto before = m.polygons();
  EXPECT_EQ(cut_by_plane(m, make_plane({0, 0, 0}, 0.5)).status, CutStatus::invalid_plane);
  EXPECT_EQ(cut_by_plane(m, make_plane({0, std::nan(""), 1}, 0.5)).status, CutStatus::invalid_plane);
  EXPECT_EQ(cut_by_plane(m, make_plane({0, 0, 1}, std::numeric_limits<double>::infinity())).status,
            CutStatus::invalid_plane);
  EXPECT_EQ(m.polygons(), before);
  HalfEdgeMesh empty;
  EXPECT_EQ(cut_by_plane(empty, make_plane({0, 0, 1}, 0.5)).status, CutStatus::invalid_mesh);
  HalfEdgeMesh nan = test::unit_cube();
  nan.vertices[3].position.x() = std::nan("");
  EXPECT_EQ(cut_by_plane(nan, make_plane({0, 0, 1}, 0.5)).status, CutStatus::invalid_mesh);
  // Edge vectors that overflow: no infinite or NaN vertex comes out.
  const double big = std::numeric_limits<double>::max() / 1.5;  // 2 big overflows
  HalfEdgeMesh huge = test::make_box(Vector3d::Constant(-big), Vector3d::Constant(big));
  const auto huge_before = huge.polygons();
  EXPECT_EQ(cut_by_plane(huge, make_plane({1, 0, 0}, 0.0)).status, CutStatus::invalid_mesh);
  EXPECT_EQ(huge.polygons(), huge_before);
  const Vector3d seg[2] = {{-big, 0, 0}, {big, 1, 0}};
  Vector3d out[3];
  const ClipResult c = clip_polygon(seg, 2, make_plane({1, 0, 0}, 0.0), out, 3);
  EXPECT_EQ(c.status, ClipStatus::invalid_input);
  EXPECT_EQ(c.count, 0u);
}

// Links within range but inconsistent (a twin pointing at the wrong
// half-edge, a broken next/prev pair, a face whose edge lies on another
// face) once sent the cut's walks out of the mesh: invalid_mesh, untouched.
TEST(CutByPlane, InconsistentLinksAreRejectedBeforeAnyWalk) {
  const auto corrupt = [](auto&& edit) {
    HalfEdgeMesh m = test::unit_cube();
    edit(m);
    const auto before = m.polygons();
    EXPECT_EQ(cut_by_plane(m, make_plane({0, 0, 1}, 0.5)).status, CutStatus::invalid_mesh);
    EXPECT_EQ(m.polygons(), before);
  };
  corrupt([](HalfEdgeMesh& m) { m.edges[0].twin = m.edges[0].next; });
  corrupt([](HalfEdgeMesh& m) { m.edges[0].twin = 0; });
  corrupt([](HalfEdgeMesh& m) { m.edges[m.edges[0].next].prev = m.edges[0].twin; });
  corrupt([](HalfEdgeMesh& m) { m.edges[0].face = (m.edges[0].face + 1) % m.faces.size(); });
  corrupt([](HalfEdgeMesh& m) { m.faces[0].edge = m.edges[m.faces[0].edge].twin; });
  corrupt([](HalfEdgeMesh& m) { m.edges[0].origin = m.edges[m.edges[0].next].origin; });
  // The intact cube still cuts.
  HalfEdgeMesh m = test::unit_cube();
  EXPECT_EQ(cut_by_plane(m, make_plane({0, 0, 1}, 0.5)).status, CutStatus::cut);
}

TEST(CutByPlane, NonConvexInputFailsAndLeavesTheMeshAlone) {
  // A cube with a pyramid dent in its top (not convex: validate() says so).
  // The plane z = 0.75 crosses it in two loops, round the sides and round
  // the dent, which no single cap can close: the cut reports it instead of
  // building a broken mesh.
  std::vector<Vector3d> pts = test::box_points(Vector3d::Zero(), Vector3d::Ones());
  pts.push_back({0.5, 0.5, 0.5});
  auto polys = test::box_polygons();
  polys[test::kTop] = {4, 5, 8};
  polys.push_back({5, 6, 8});
  polys.push_back({6, 7, 8});
  polys.push_back({7, 4, 8});
  HalfEdgeMesh m = test::mesh_from(pts, polys);
  ASSERT_FALSE(m.validate().ok());
  const HalfEdgeMesh before = m;
  const CutResult r = cut_by_plane(m, make_plane({0, 0, 1}, 0.75));
  EXPECT_EQ(r.status, CutStatus::topology_failure);
  EXPECT_EQ(m.polygons(), before.polygons());
  for (Index v = 0; v < m.vertex_count(); ++v) EXPECT_EQ(m.position(v), before.position(v));
  // Below the dent, one loop again: a clean cut.
  EXPECT_EQ(cut_by_plane(m, make_plane({0, 0, 1}, 0.25)).status, CutStatus::cut);
  EXPECT_TRUE(m.validate().ok()) << m.validate().to_string();
}

TEST(CutByPlane, CompactsAfterEdits) {
  // Edit first (split an edge, split a face), then cut: the result has no
  // unused element and keeps the surviving faces' relative order.
  HalfEdgeMesh m = test::unit_cube();
  const Index mid = split_edge(m, find_edge(m, 4, 5), {0.5, 0, 1});
  ASSERT_NE(split_face(m, test::kTop, mid, 7), kInvalidIndex);
  ASSERT_TRUE(m.validate().ok());
  const CutResult r = cut_by_plane(m, make_plane({0, 0, 1}, 0.25));
  ASSERT_EQ(r.status, CutStatus::cut);
  EXPECT_TRUE(m.validate().ok()) << m.validate().to_string();
  EXPECT_EQ(m.vertex_count(), 8u);  // 4 bottom + 4 crossings; 5 top vertices gone
  EXPECT_EQ(m.face_count(), 6u);
  EXPECT_EQ(r.removed_vertices, 5u);
  EXPECT_EQ(r.added_vertices, 4u);
  EXPECT_EQ(r.face_source,
            (std::vector<Index>{test::kBottom, test::kFront, test::kBack, test::kLeft, test::kRight, kInvalidIndex}));
  for (Index v = 0; v < m.vertex_count(); ++v) EXPECT_NE(m.vertices[v].edge, kInvalidIndex);
  EXPECT_NEAR(volume(m), 0.25, 1e-15);
}

// ---- property tests ------------------------------------------------------------

struct HalvesCheck {
  int cut = 0, unchanged = 0, emptied = 0;
};

// Cuts `mesh` by `plane` and by the flipped plane and checks both halves.
void check_halves(const HalfEdgeMesh& mesh, const Plane& plane, double total_volume, HalvesCheck& tally) {
  SCOPED_TRACE(describe(plane));
  HalfEdgeMesh a = mesh, b = mesh;
  const CutResult ra = cut_by_plane(a, plane);
  const CutResult rb = cut_by_plane(b, flipped(plane));
  ASSERT_NE(ra.status, CutStatus::topology_failure);
  ASSERT_NE(rb.status, CutStatus::topology_failure);
  const double vol_tol = 1e-11 * total_volume;
  if (ra.status == CutStatus::cut) {
    // A cut on one side is a cut on the other (both sides have a vertex
    // beyond tolerance).
    ASSERT_EQ(rb.status, CutStatus::cut);
    ++tally.cut;
    EXPECT_TRUE(a.validate().ok()) << a.validate().to_string();
    EXPECT_TRUE(b.validate().ok()) << b.validate().to_string();
    const double va = volume(a), vb = volume(b);
    EXPECT_GT(va, 0);
    EXPECT_GT(vb, 0);
    EXPECT_NEAR(va + vb, total_volume, vol_tol);
    // The caps are the same polygon, one wound the other way.
    EXPECT_EQ(a.face_degree(ra.cap_face), b.face_degree(rb.cap_face));
    EXPECT_NEAR(face_area(a, ra.cap_face), face_area(b, rb.cap_face), 1e-12 * total_volume);
    EXPECT_EQ(ra.added_vertices, rb.added_vertices);
    // New vertices are not near-duplicates of kept input vertices (snapping).
    const double tol = mesh.tolerance();
    for (Index v = static_cast<Index>(a.vertex_count() - ra.added_vertices); v < a.vertex_count(); ++v)
      for (Index w = 0; w < mesh.vertex_count(); ++w) EXPECT_GT((a.position(v) - mesh.position(w)).norm(), tol);
  } else if (ra.status == CutStatus::unchanged) {
    ++tally.unchanged;
    EXPECT_EQ(rb.status, CutStatus::emptied);
    EXPECT_EQ(a.polygons(), mesh.polygons());
  } else {
    ++tally.emptied;
    EXPECT_EQ(ra.status, CutStatus::emptied);
    EXPECT_EQ(rb.status, CutStatus::unchanged);
  }
}

TEST(CutByPlaneProperty, RandomPlanesThroughRandomSolids) {
  std::mt19937_64 rng(20240611);
  std::normal_distribution<double> gauss;
  std::uniform_real_distribution<double> u(-1.2, 1.2);
  HalvesCheck tally;
  for (int mesh_i = 0; mesh_i < 40; ++mesh_i) {
    const HalfEdgeMesh mesh = test::random_convex_solid(rng, 1.0);
    ASSERT_TRUE(mesh.validate().ok()) << mesh.validate().to_string();
    const double total = volume(mesh);
    for (int k = 0; k < 15; ++k) {
      const Vector3d n(gauss(rng), gauss(rng), gauss(rng));
      const Vector3d through(u(rng), u(rng), u(rng));
      check_halves(mesh, make_plane(n.normalized(), n.normalized().dot(through)), total, tally);
      if (HasFatalFailure()) return;
    }
  }
  // The sample reaches every outcome, mostly cuts.
  EXPECT_GT(tally.cut, 300);
  EXPECT_GT(tally.unchanged, 5);
  EXPECT_GT(tally.emptied, 5);
}

TEST(CutByPlaneProperty, RepeatedCutsOfABox) {
  // A box whittled by 30 random planes through points near its centre: every
  // intermediate result validates, and each removed piece (the flipped cut)
  // accounts for the volume lost.
  std::mt19937_64 rng(99);
  std::normal_distribution<double> gauss;
  // |n . q| <= 0.35 < 0.4: the origin stays strictly behind every plane.
  std::uniform_real_distribution<double> u(-0.2, 0.2);
  for (int trial = 0; trial < 10; ++trial) {
    HalfEdgeMesh m = test::make_box({-1, -1.5, -0.5}, {1, 1.5, 0.5});
    double vol = volume(m);
    for (int k = 0; k < 30; ++k) {
      const Vector3d n = Vector3d(gauss(rng), gauss(rng), gauss(rng)).normalized();
      const Plane p = make_plane(n, n.dot(Vector3d(u(rng), u(rng), u(rng))) + 0.4);
      SCOPED_TRACE(describe(p));
      HalfEdgeMesh piece = m;
      const CutResult r = cut_by_plane(m, p);
      ASSERT_TRUE(r.status == CutStatus::cut || r.status == CutStatus::unchanged) << to_string(r.status);
      ASSERT_TRUE(m.validate().ok()) << m.validate().to_string();
      double removed = 0;
      if (r.status == CutStatus::cut) {
        ASSERT_EQ(cut_by_plane(piece, flipped(p)).status, CutStatus::cut);
        ASSERT_TRUE(piece.validate().ok()) << piece.validate().to_string();
        removed = volume(piece);
      }
      const double now = volume(m);
      EXPECT_NEAR(now + removed, vol, 1e-12);
      vol = now;
    }
    EXPECT_GT(m.face_count(), 10u);
  }
}

TEST(CutByPlaneProperty, PlanesThroughFeatures) {
  // Planes through existing vertices (3 random vertices, 2 vertices and a
  // random direction, 1 vertex and a random normal), through face planes
  // exactly and nudged by fractions of the tolerance: each must cut cleanly
  // or leave the mesh alone, never fail.
  std::mt19937_64 rng(4242);
  std::normal_distribution<double> gauss;
  HalvesCheck tally;
  for (int mesh_i = 0; mesh_i < 30; ++mesh_i) {
    const HalfEdgeMesh mesh = mesh_i % 3 == 0 ? test::random_convex_solid(rng, 10.0, Vector3d(1e3, -2e3, 5e2))
                                              : test::random_convex_solid(rng, 1.0);
    const double total = volume(mesh);
    const double tol = mesh.tolerance();
    std::uniform_int_distribution<Index> pick(0, static_cast<Index>(mesh.vertex_count() - 1));
    for (int k = 0; k < 10; ++k) {
      const Vector3d a = mesh.position(pick(rng)), b = mesh.position(pick(rng)), c = mesh.position(pick(rng));
      Vector3d n = (b - a).cross(c - a);
      // (Skipped only when the picks coincide or are exactly collinear.)
      if (n.norm() > 0) check_halves(mesh, make_plane(n.normalized(), n.normalized().dot(a)), total, tally);
      const Vector3d r(gauss(rng), gauss(rng), gauss(rng));
      n = (b - a).cross(r);
      if (n.norm() > 0) check_halves(mesh, make_plane(n.normalized(), n.normalized().dot(a)), total, tally);
      n = r.normalized();
      check_halves(mesh, make_plane(n, n.dot(a)), total, tally);
      for (double nudge : {-3.0, -0.7, 0.7, 3.0})
        check_halves(mesh, make_plane(n, n.dot(a) + nudge * tol), total, tally);
      if (HasFatalFailure()) return;
    }
    for (Index f = 0; f < mesh.face_count(); ++f) {
      const Plane& p = mesh.plane(f);
      for (double nudge : {0.0, -0.5, 0.5, -4.0})
        check_halves(mesh, make_plane(p.normal, p.offset + nudge * tol), total, tally);
      if (HasFatalFailure()) return;
    }
  }
  EXPECT_GT(tally.cut, 500);
  EXPECT_GT(tally.unchanged + tally.emptied, 300);
}

TEST(CutByPlaneProperty, RandomFlatPolygons) {
  std::mt19937_64 rng(5);
  std::normal_distribution<double> gauss;
  int cuts = 0;
  for (int i = 0; i < 100; ++i) {
    const auto base = test::random_convex_polygon(rng, 3 + static_cast<int>(rng() % 10), 1.0, 0.6);
    std::vector<Vector3d> pts;
    for (const auto& p : base) pts.emplace_back(p.x(), p.y(), 0.3);
    const HalfEdgeMesh flat = test::make_flat_polygon(pts);
    const double area = face_area(flat, 0);
    const Vector3d n = Vector3d(gauss(rng), gauss(rng), 0.2 * gauss(rng)).normalized();
    const Plane p = make_plane(n, n.dot(Vector3d(0.5 * gauss(rng), 0.3 * gauss(rng), 0.3)));
    SCOPED_TRACE(describe(p));
    HalfEdgeMesh a = flat, b = flat;
    const CutResult ra = cut_by_plane(a, p), rb = cut_by_plane(b, flipped(p));
    if (ra.status != CutStatus::cut) continue;
    ++cuts;
    ASSERT_EQ(rb.status, CutStatus::cut);
    EXPECT_TRUE(a.validate().ok()) << a.validate().to_string();
    EXPECT_TRUE(b.validate().ok()) << b.validate().to_string();
    EXPECT_EQ(a.face_count(), 2u);
    EXPECT_NEAR(face_area(a, 0) + face_area(b, 0), area, 1e-14);
    // Same as clipping the polygon directly.
    std::vector<Vector3d> out(pts.size() + 1);
    const ClipResult c = clip_polygon(pts.data(), pts.size(), p, out.data(), out.size());
    ASSERT_EQ(c.status, ClipStatus::ok);
    EXPECT_EQ(c.count, a.vertex_count());
    EXPECT_NEAR(polygon_area(out.data(), c.count), face_area(a, 0), 1e-14);
  }
  EXPECT_GT(cuts, 50);
}

// ---- clip_polygon --------------------------------------------------------------

TEST(ClipPolygon, Square) {
  const Vector3d sq[4] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  Vector3d out[8];
  ClipResult r = clip_polygon(sq, 4, make_plane({1, 0, 0}, 0.25), out, 8);
  ASSERT_EQ(r.status, ClipStatus::ok);
  ASSERT_EQ(r.count, 4u);
  EXPECT_EQ(out[0], Vector3d(0, 0, 0));
  EXPECT_EQ(out[1], Vector3d(0.25, 0, 0));
  EXPECT_EQ(out[2], Vector3d(0.25, 1, 0));
  EXPECT_EQ(out[3], Vector3d(0, 1, 0));
  // Corner cut: a pentagon (n + 1 points).
  r = clip_polygon(sq, 4, make_plane({1, 1, 0}, 1.5), out, 8);
  EXPECT_EQ(r.count, 5u);
  EXPECT_NEAR(polygon_area(out, r.count), 1 - 0.125, 1e-15);
  // Diagonal through two corners: a triangle, the corners not duplicated.
  r = clip_polygon(sq, 4, make_plane({1, 1, 0}, 1.0), out, 8);
  ASSERT_EQ(r.count, 3u);
  EXPECT_EQ(out[0], sq[0]);
  EXPECT_EQ(out[1], sq[1]);
  EXPECT_EQ(out[2], sq[3]);
  // Within tolerance of a corner: kept as is.
  r = clip_polygon(sq, 4, make_plane({1, 1, 0}, 2.0 - 1e-15), out, 8, 1e-12);
  EXPECT_EQ(r.count, 4u);
  EXPECT_EQ(out[2], sq[2]);
  // Touching along an edge from outside: the edge remains.
  r = clip_polygon(sq, 4, make_plane({-1, 0, 0}, -1.0), out, 8);
  ASSERT_EQ(r.count, 2u);
  EXPECT_EQ(out[0], sq[1]);
  EXPECT_EQ(out[1], sq[2]);
  // Entirely in front.
  r = clip_polygon(sq, 4, make_plane({0, 0, 1}, -1.0), out, 8);
  EXPECT_EQ(r.status, ClipStatus::ok);
  EXPECT_EQ(r.count, 0u);
  // Unnormalised plane gives the same answer as the normalised one.
  r = clip_polygon(sq, 4, make_plane({10, 0, 0}, 2.5), out, 8);
  EXPECT_EQ(r.count, 4u);
  EXPECT_EQ(out[1], Vector3d(0.25, 0, 0));
}

TEST(ClipPolygon, CapacityAndInvalidInput) {
  const Vector3d sq[4] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  Vector3d out[4];
  ClipResult r = clip_polygon(sq, 4, make_plane({1, 1, 0}, 1.5), out, 4);
  EXPECT_EQ(r.status, ClipStatus::capacity_exceeded);
  EXPECT_EQ(r.count, 4u);
  r = clip_polygon(sq, 4, make_plane({0, 0, 0}, 1.5), out, 4);
  EXPECT_EQ(r.status, ClipStatus::invalid_input);
  EXPECT_EQ(r.count, 0u);
  const Vector3d bad[3] = {{0, 0, 0}, {1, std::nan(""), 0}, {0, 1, 0}};
  EXPECT_EQ(clip_polygon(bad, 3, make_plane({1, 0, 0}, 0.5), out, 4).status, ClipStatus::invalid_input);
  EXPECT_EQ(clip_polygon(sq, 0, make_plane({1, 0, 0}, 0.5), out, 4).count, 0u);
}

TEST(ClipPolygon, SegmentsAndPoints) {
  const Vector3d seg[2] = {{0, 0, 0}, {2, 0, 0}};
  Vector3d out[3];
  ClipResult r = clip_polygon(seg, 2, make_plane({1, 0, 0}, 0.5), out, 3);
  ASSERT_EQ(r.count, 2u);
  EXPECT_EQ(out[0], seg[0]);
  EXPECT_EQ(out[1], Vector3d(0.5, 0, 0));
  r = clip_polygon(seg, 2, make_plane({-1, 0, 0}, -0.5), out, 3);
  ASSERT_EQ(r.count, 2u);
  EXPECT_EQ(out[0], Vector3d(0.5, 0, 0));
  EXPECT_EQ(out[1], seg[1]);
  r = clip_polygon(seg, 2, make_plane({1, 0, 0}, 0.0), out, 3);  // touches at seg[0]
  ASSERT_EQ(r.count, 1u);
  EXPECT_EQ(out[0], seg[0]);
  EXPECT_EQ(clip_polygon(seg, 1, make_plane({1, 0, 0}, -1.0), out, 3).count, 0u);
  EXPECT_EQ(clip_polygon(seg, 1, make_plane({1, 0, 0}, 1.0), out, 3).count, 1u);
}

TEST(ClipPolygon, RandomPolygonsAreaAddsUpAndStaysConvex) {
  std::mt19937_64 rng(11);
  std::normal_distribution<double> gauss;
  int both = 0;
  for (int i = 0; i < 300; ++i) {
    const int n = 3 + static_cast<int>(rng() % 14);
    const auto base = test::random_convex_polygon(rng, n, 2.0, 1.0);
    // Put the polygon in a random plane, far from the origin half the time.
    const Eigen::Matrix3d R =
        Eigen::Quaterniond(gauss(rng), gauss(rng), gauss(rng), gauss(rng)).normalized().toRotationMatrix();
    const Vector3d offset = i % 2 ? Vector3d(1e5, -3e5, 2e5) : Vector3d::Zero();
    std::vector<Vector3d> pts;
    for (const auto& p : base) pts.push_back(R * Vector3d(p.x(), p.y(), 0) + offset);
    const Vector3d dir = R * Vector3d(gauss(rng), gauss(rng), 0.1 * gauss(rng));
    const Vector3d n_hat = dir.normalized();
    const Plane p = make_plane(n_hat, n_hat.dot(offset + R * Vector3d(gauss(rng), 0.5 * gauss(rng), 0)));
    std::vector<Vector3d> a(n + 1), b(n + 1);
    const ClipResult ra = clip_polygon(pts.data(), pts.size(), p, a.data(), a.size());
    const ClipResult rb = clip_polygon(pts.data(), pts.size(), flipped(p), b.data(), b.size());
    ASSERT_EQ(ra.status, ClipStatus::ok);
    ASSERT_EQ(rb.status, ClipStatus::ok);
    EXPECT_LE(ra.count, static_cast<std::size_t>(n + 1));
    const double area = polygon_area(pts.data(), pts.size());
    const double aa = polygon_area(a.data(), ra.count), ab = polygon_area(b.data(), rb.count);
    const double tol = 64 * std::numeric_limits<double>::epsilon() * (4 + offset.norm());
    EXPECT_NEAR(aa + ab, area, tol);
    if (ra.count >= 3 && rb.count >= 3) ++both;
    // Kept points are behind the plane (within tolerance).
    for (std::size_t k = 0; k < ra.count; ++k) EXPECT_LE(p.signed_distance(a[k]), tol);
  }
  EXPECT_GT(both, 100);
}

}  // namespace
}  // namespace hedra::hull
