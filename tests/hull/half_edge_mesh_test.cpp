// Tests of the half-edge mesh: construction from polygons (cube, tetrahedron,
// prism, flat polygon, and each rejected input), every navigation accessor
// and range against answers worked out by hand on the unit cube, and
// validate(): it passes on good meshes and names each broken invariant when a
// copy is corrupted on purpose (one test per invariant).
#include <gtest/gtest.h>

#include <algorithm>
#include <hedra/hull/half_edge_mesh.hpp>
#include <vector>

#include "test_meshes.hpp"

namespace hedra::hull {
namespace {

using Eigen::Vector3d;
using test::kBack;
using test::kBottom;
using test::kFront;
using test::kLeft;
using test::kRight;
using test::kTop;

template <class Range>
std::vector<Index> collect(const Range& range) {
  std::vector<Index> out;
  for (Index i : range) out.push_back(i);
  return out;
}

// Equal as cyclic sequences (the start of a ring is an arbitrary choice).
bool same_cycle(const std::vector<Index>& a, const std::vector<Index>& b) {
  if (a.size() != b.size()) return false;
  if (a.empty()) return true;
  for (std::size_t shift = 0; shift < a.size(); ++shift) {
    bool all = true;
    for (std::size_t i = 0; i < a.size() && all; ++i) all = a[(i + shift) % a.size()] == b[i];
    if (all) return true;
  }
  return false;
}

// The half-edge a -> b, found by brute force (independent of the ranges).
Index find_edge(const HalfEdgeMesh& m, Index a, Index b) {
  for (Index e = 0; e < m.edges.size(); ++e)
    if (m.edges[e].origin == a && m.edges[m.edges[e].twin].origin == b) return e;
  return kInvalidIndex;
}

bool has_error(const ValidationReport& r, const std::string& what) {
  return std::any_of(r.errors.begin(), r.errors.end(),
                     [&](const std::string& e) { return e.find(what) != std::string::npos; });
}

// ---- construction ---------------------------------------------------------

TEST(FromPolygons, CubeCountsPlanesAndTolerance) {
  const HalfEdgeMesh m = test::unit_cube();
  EXPECT_EQ(m.vertex_count(), 8u);
  EXPECT_EQ(m.half_edge_count(), 24u);
  EXPECT_EQ(m.edge_count(), 12u);
  EXPECT_EQ(m.face_count(), 6u);
  EXPECT_EQ(m.dimension(), 3);
  EXPECT_GT(m.tolerance(), 0.0);
  EXPECT_LT(m.tolerance(), 1e-12);
  EXPECT_TRUE(m.validate().ok()) << m.validate().to_string();
  const Vector3d normals[6] = {{0, 0, -1}, {0, 0, 1}, {0, -1, 0}, {0, 1, 0}, {-1, 0, 0}, {1, 0, 0}};
  const double offsets[6] = {0, 1, 0, 1, 0, 1};
  for (Index f = 0; f < 6; ++f) {
    EXPECT_LT((m.plane(f).normal - normals[f]).norm(), 1e-15) << "face " << f;
    EXPECT_NEAR(m.plane(f).offset, offsets[f], 1e-15) << "face " << f;
  }
  EXPECT_EQ(m.polygons(), test::box_polygons());
}

TEST(FromPolygons, TetrahedronPrismAndFlatPolygon) {
  const HalfEdgeMesh tet = test::make_tetrahedron({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1});
  EXPECT_EQ(tet.vertex_count(), 4u);
  EXPECT_EQ(tet.edge_count(), 6u);
  EXPECT_EQ(tet.face_count(), 4u);
  EXPECT_EQ(tet.dimension(), 3);
  EXPECT_TRUE(tet.validate().ok()) << tet.validate().to_string();

  // The same tetrahedron from points in the other orientation.
  const HalfEdgeMesh tet2 = test::make_tetrahedron({0, 0, 0}, {0, 1, 0}, {1, 0, 0}, {0, 0, 1});
  EXPECT_TRUE(tet2.validate().ok()) << tet2.validate().to_string();

  const HalfEdgeMesh prism = test::make_prism(test::regular_polygon(6, 1.0), -0.5, 0.5);
  EXPECT_EQ(prism.vertex_count(), 12u);
  EXPECT_EQ(prism.edge_count(), 18u);
  EXPECT_EQ(prism.face_count(), 8u);
  EXPECT_EQ(prism.face_degree(0), 6u);
  EXPECT_EQ(prism.face_degree(2), 4u);
  EXPECT_TRUE(prism.validate().ok()) << prism.validate().to_string();

  const HalfEdgeMesh flat = test::make_flat_polygon({{0, 0, 2}, {1, 0, 2}, {1.5, 1, 2}, {0, 1, 2}});
  EXPECT_EQ(flat.vertex_count(), 4u);
  EXPECT_EQ(flat.edge_count(), 4u);
  EXPECT_EQ(flat.face_count(), 2u);
  EXPECT_EQ(flat.dimension(), 2);
  EXPECT_TRUE(flat.validate().ok()) << flat.validate().to_string();
  EXPECT_LT((flat.plane(0).normal - Vector3d(0, 0, 1)).norm(), 1e-15);
  EXPECT_LT((flat.plane(1).normal - Vector3d(0, 0, -1)).norm(), 1e-15);
  // The two faces share the ring: every half-edge's twin is in the other face.
  for (Index e = 0; e < flat.edges.size(); ++e) EXPECT_NE(flat.left_face(e), flat.right_face(e));
}

TEST(FromPolygons, RejectsBrokenInput) {
  const auto pts = test::box_points(Vector3d::Zero(), Vector3d::Ones());
  HalfEdgeMesh out;
  std::string error;
  auto polys = test::box_polygons();

  auto two = polys;
  two[0] = {0, 3};
  EXPECT_FALSE(HalfEdgeMesh::from_polygons(pts, two, out, &error));
  EXPECT_NE(error.find("fewer than 3"), std::string::npos) << error;

  auto range = polys;
  range[1][2] = 8;
  EXPECT_FALSE(HalfEdgeMesh::from_polygons(pts, range, out, &error));
  EXPECT_NE(error.find("out of range"), std::string::npos) << error;

  auto repeat = polys;
  repeat[1] = {4, 5, 5, 7};
  EXPECT_FALSE(HalfEdgeMesh::from_polygons(pts, repeat, out, &error));
  EXPECT_NE(error.find("repeats vertex"), std::string::npos) << error;

  auto flipped = polys;
  std::reverse(flipped[1].begin(), flipped[1].end());  // top face wound inward
  EXPECT_FALSE(HalfEdgeMesh::from_polygons(pts, flipped, out, &error));
  EXPECT_NE(error.find("same direction"), std::string::npos) << error;

  auto open = polys;
  open.pop_back();  // no right face
  EXPECT_FALSE(HalfEdgeMesh::from_polygons(pts, open, out, &error));
  EXPECT_NE(error.find("open surface"), std::string::npos) << error;
}

// ---- navigation on the unit cube -------------------------------------------

TEST(Navigation, FaceRanges) {
  const HalfEdgeMesh m = test::unit_cube();
  const auto polys = test::box_polygons();
  for (Index f = 0; f < 6; ++f) {
    // face.edge is the polygon's first edge, so the order is exact.
    EXPECT_EQ(collect(m.face_vertices(f)), polys[f]) << "face " << f;
    const auto edges = collect(m.face_edges(f));
    ASSERT_EQ(edges.size(), 4u);
    for (std::size_t i = 0; i < 4; ++i) {
      const Index e = edges[i];
      EXPECT_EQ(m.origin(e), polys[f][i]);
      EXPECT_EQ(m.destination(e), polys[f][(i + 1) % 4]);
      EXPECT_EQ(m.left_face(e), f);
      EXPECT_EQ(m.next(e), edges[(i + 1) % 4]);
      EXPECT_EQ(m.prev(e), edges[(i + 3) % 4]);
      EXPECT_EQ(m.twin(e), find_edge(m, polys[f][(i + 1) % 4], polys[f][i]));
      EXPECT_EQ((m.edge_vector(e) - (m.position(polys[f][(i + 1) % 4]) - m.position(polys[f][i]))).norm(), 0.0);
    }
    EXPECT_EQ(m.face_degree(f), 4u);
  }
  // Neighbours across bottom edges 0-3, 3-2, 2-1, 1-0: left, back, right, front.
  EXPECT_EQ(collect(m.face_neighbors(kBottom)), (std::vector<Index>{kLeft, kBack, kRight, kFront}));
  // Across top edges 4-5, 5-6, 6-7, 7-4: front, right, back, left.
  EXPECT_EQ(collect(m.face_neighbors(kTop)), (std::vector<Index>{kFront, kRight, kBack, kLeft}));
  EXPECT_EQ(collect(m.face_neighbors(kRight)), (std::vector<Index>{kBottom, kBack, kTop, kFront}));
}

TEST(Navigation, LeftAndRightFaceOfAnEdge) {
  const HalfEdgeMesh m = test::unit_cube();
  const Index e01 = find_edge(m, 0, 1);
  ASSERT_NE(e01, kInvalidIndex);
  EXPECT_EQ(m.left_face(e01), kFront);
  EXPECT_EQ(m.right_face(e01), kBottom);
  EXPECT_EQ(m.origin(e01), 0u);
  EXPECT_EQ(m.destination(e01), 1u);
  const Index e56 = find_edge(m, 5, 6);
  EXPECT_EQ(m.left_face(e56), kTop);
  EXPECT_EQ(m.right_face(e56), kRight);
  EXPECT_EQ(m.left_face(m.twin(e56)), kRight);
  EXPECT_EQ(m.right_face(m.twin(e56)), kTop);
}

TEST(Navigation, VertexRangesAroundCorner0And6) {
  const HalfEdgeMesh m = test::unit_cube();
  // Seen from outside corner 0 (from -1,-1,-1), counter-clockwise: the edges
  // to 3 (+y), 1 (+x), 4 (+z); (y x x) . (-1,-1,-1) > 0 confirms the sense.
  EXPECT_TRUE(same_cycle(collect(m.vertex_neighbors(0)), {3, 1, 4}))
      << ::testing::PrintToString(collect(m.vertex_neighbors(0)));
  // Faces to the left of those edges: bottom (0->3), front (0->1), left (0->4).
  EXPECT_TRUE(same_cycle(collect(m.vertex_faces(0)), {kBottom, kFront, kLeft}));
  const auto out0 = collect(m.vertex_outgoing(0));
  ASSERT_EQ(out0.size(), 3u);
  for (Index e : out0) EXPECT_EQ(m.origin(e), 0u);
  const auto in0 = collect(m.vertex_incoming(0));
  ASSERT_EQ(in0.size(), 3u);
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(m.destination(in0[i]), 0u);
    EXPECT_EQ(in0[i], m.twin(out0[i]));
  }
  // Corner 6 = (1,1,1), seen from (2,2,2): 7 (-x), 5 (-y), 2 (-z) counter-clockwise.
  EXPECT_TRUE(same_cycle(collect(m.vertex_neighbors(6)), {2, 7, 5}))
      << ::testing::PrintToString(collect(m.vertex_neighbors(6)));
  EXPECT_TRUE(same_cycle(collect(m.vertex_faces(6)), {kBack, kTop, kRight}));
  for (Index v = 0; v < 8; ++v) EXPECT_EQ(m.vertex_degree(v), 3u);
}

TEST(Navigation, RotationsAreInverseAndStayAtTheVertex) {
  const HalfEdgeMesh m = test::unit_cube();
  for (Index e = 0; e < m.edges.size(); ++e) {
    EXPECT_EQ(m.origin(m.rotate_ccw(e)), m.origin(e));
    EXPECT_EQ(m.origin(m.rotate_cw(e)), m.origin(e));
    EXPECT_NE(m.rotate_ccw(e), e);
    EXPECT_EQ(m.rotate_cw(m.rotate_ccw(e)), e);
    EXPECT_EQ(m.rotate_ccw(m.rotate_cw(e)), e);
    // Three edges at each corner: three steps come back.
    EXPECT_EQ(m.rotate_ccw(m.rotate_ccw(m.rotate_ccw(e))), e);
  }
  // At corner 0: 0->3, then 0->1, then 0->4 counter-clockwise.
  const Index e03 = find_edge(m, 0, 3), e01 = find_edge(m, 0, 1), e04 = find_edge(m, 0, 4);
  EXPECT_EQ(m.rotate_ccw(e03), e01);
  EXPECT_EQ(m.rotate_ccw(e01), e04);
  EXPECT_EQ(m.rotate_cw(e01), e03);
  EXPECT_EQ(m.rotate_cw(e03), e04);
}

TEST(Navigation, GeometryHelpers) {
  const HalfEdgeMesh m = test::make_box({-1, -2, -3}, {1, 2, 3});
  EXPECT_EQ(m.extreme_vertex({1, 1, 1}), 6u);
  EXPECT_EQ(m.extreme_vertex({-1, -1, -1}), 0u);
  EXPECT_EQ(m.extreme_vertex({1, -1, 1}), 5u);
  EXPECT_EQ((m.face_centroid(kTop) - Vector3d(0, 0, 3)).norm(), 0.0);
  EXPECT_EQ((m.face_centroid(kLeft) - Vector3d(-1, 0, 0)).norm(), 0.0);
  HalfEdgeMesh copy = m;
  copy.faces[kTop].plane = Plane{};
  copy.update_plane(kTop);
  EXPECT_LT((copy.plane(kTop).normal - Vector3d(0, 0, 1)).norm(), 1e-15);
  EXPECT_NEAR(copy.plane(kTop).offset, 3.0, 1e-15);
}

TEST(Navigation, EmptyRangeForVertexWithoutEdges) {
  const HalfEdgeMesh point = test::make_vertices_only({{1, 2, 3}}, 1e-12);
  EXPECT_EQ(point.dimension(), 0);
  EXPECT_TRUE(collect(point.vertex_outgoing(0)).empty());
  EXPECT_TRUE(point.validate().ok());
  const HalfEdgeMesh segment = test::make_vertices_only({{0, 0, 0}, {1, 0, 0}}, 1e-12);
  EXPECT_EQ(segment.dimension(), 1);
  EXPECT_TRUE(segment.validate().ok());
  const HalfEdgeMesh bad_segment = test::make_vertices_only({{0, 0, 0}, {0, 0, 0}}, 1e-12);
  EXPECT_TRUE(has_error(bad_segment.validate(), "coincident"));
  EXPECT_EQ(HalfEdgeMesh().dimension(), -1);
}

// ---- validate(): one deliberately broken invariant at a time ------------------

TEST(Validate, GoodMeshesPass) {
  for (const HalfEdgeMesh& m :
       {test::unit_cube(), test::make_box({1e6, -1e6, 5}, {1e6 + 1, -1e6 + 2, 8}),
        test::make_tetrahedron({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}),
        test::make_prism(test::regular_polygon(9, 2.0), 0, 1), test::make_bipyramid(test::regular_polygon(5, 1), 1, 2)})
    EXPECT_TRUE(m.validate().ok()) << m.validate().to_string();
}

TEST(Validate, BrokenTwin) {
  HalfEdgeMesh m = test::unit_cube();
  const Index e = find_edge(m, 0, 1);
  m.edges[e].twin = find_edge(m, 1, 2);
  EXPECT_TRUE(has_error(m.validate(), "twin(twin(e)) != e")) << m.validate().to_string();
}

TEST(Validate, BrokenNextPrev) {
  HalfEdgeMesh m = test::unit_cube();
  const Index e = find_edge(m, 0, 1);
  m.edges[e].prev = m.edges[e].next;  // prev no longer points back round the face
  EXPECT_TRUE(has_error(m.validate(), "prev(next(e)) != e")) << m.validate().to_string();
  HalfEdgeMesh m2 = test::unit_cube();
  m2.edges[e].next = m2.edges[e].prev;
  EXPECT_TRUE(has_error(m2.validate(), "next(prev(e)) != e")) << m2.validate().to_string();
}

TEST(Validate, BrokenFaceLinks) {
  HalfEdgeMesh m = test::unit_cube();
  m.edges[find_edge(m, 0, 1)].face = kTop;
  EXPECT_TRUE(has_error(m.validate(), "face(next(e)) != face(e)")) << m.validate().to_string();
  HalfEdgeMesh m2 = test::unit_cube();
  m2.faces[kTop].edge = m2.faces[kBottom].edge;
  EXPECT_TRUE(has_error(m2.validate(), "face(face.edge) != face")) << m2.validate().to_string();
}

TEST(Validate, BrokenVertexBackLink) {
  HalfEdgeMesh m = test::unit_cube();
  m.vertices[0].edge = find_edge(m, 1, 0);  // arrives at 0 instead of leaving it
  EXPECT_TRUE(has_error(m.validate(), "origin(vertex.edge) != vertex")) << m.validate().to_string();
}

TEST(Validate, TwoEdgeFace) {
  // Open the edge 0-3 into a digon: the two new half-edges form a face of
  // their own between bottom and left. Every link stays consistent (and
  // Euler still holds), only the face has two edges.
  HalfEdgeMesh m = test::unit_cube();
  const Index e = find_edge(m, 0, 3), t = m.twin(e);
  const Index d1 = static_cast<Index>(m.edges.size()), d2 = d1 + 1;
  const Index digon = static_cast<Index>(m.faces.size());
  m.edges.push_back({3, e, d2, d2, digon});  // 3 -> 0
  m.edges.push_back({0, t, d1, d1, digon});  // 0 -> 3
  m.edges[e].twin = d1;
  m.edges[t].twin = d2;
  m.faces.push_back({d1, m.faces[kBottom].plane});
  const ValidationReport r = m.validate();
  EXPECT_TRUE(has_error(r, "fewer than 3 edges")) << r.to_string();
  EXPECT_FALSE(has_error(r, "twin(twin(e))"));
  EXPECT_FALSE(has_error(r, "not a manifold vertex"));
}

TEST(Validate, EulerViolation) {
  // Two disjoint tetrahedra: a closed 2-manifold, but V - E + F = 4.
  std::vector<Vector3d> pts = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {5, 0, 0}, {6, 0, 0}, {5, 1, 0}, {5, 0, 1}};
  std::vector<std::vector<Index>> polys = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2},
                                           {4, 6, 5}, {4, 5, 7}, {5, 6, 7}, {4, 7, 6}};
  const HalfEdgeMesh m = test::mesh_from(pts, polys);
  const ValidationReport r = m.validate();
  EXPECT_TRUE(has_error(r, "Euler characteristic V - E + F = 4")) << r.to_string();
}

TEST(Validate, NonManifoldVertex) {
  // Two tetrahedra sharing vertex 0 only: its ring is two fans.
  std::vector<Vector3d> pts = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {-1, 0, 0}, {0, -1, 0}, {0, 0, -1}};
  std::vector<std::vector<Index>> polys = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2},
                                           {0, 5, 4}, {0, 4, 6}, {4, 5, 6}, {0, 6, 5}};
  const HalfEdgeMesh m = test::mesh_from(pts, polys);
  EXPECT_TRUE(has_error(m.validate(), "not a manifold vertex")) << m.validate().to_string();
}

TEST(Validate, NonPlanarFace) {
  HalfEdgeMesh m = test::unit_cube();
  m.vertices[6].position.z() = 0.9;  // still on the right and back planes, below the top
  const ValidationReport r = m.validate();
  EXPECT_TRUE(has_error(r, "face 1: vertex 6 is")) << r.to_string();
  EXPECT_TRUE(has_error(r, "off the face plane"));
  EXPECT_FALSE(has_error(r, "face 5: vertex 6"));  // the right face still holds it
}

TEST(Validate, NonConvexFace) {
  // A dart: the fourth vertex is reflex.
  const HalfEdgeMesh m = test::make_flat_polygon({{0, 0, 0}, {2, 1, 0}, {0, 2, 0}, {1, 1, 0}});
  const ValidationReport r = m.validate();
  EXPECT_TRUE(has_error(r, "is not convex at vertex 3")) << r.to_string();
  // The same ring with a convex fourth vertex passes.
  EXPECT_TRUE(test::make_flat_polygon({{0, 0, 0}, {2, 1, 0}, {0, 2, 0}, {-1, 1, 0}}).validate().ok());
}

TEST(Validate, StarPolygonWindsTwice) {
  // A pentagram: every corner turns the same way (so each local convexity
  // test passes) but the ring goes round twice.
  std::vector<Vector3d> pts;
  for (int i : {0, 2, 4, 1, 3}) pts.emplace_back(std::cos(2 * M_PI * i / 5), std::sin(2 * M_PI * i / 5), 0);
  const HalfEdgeMesh star = test::make_flat_polygon(pts);
  const ValidationReport r = star.validate();
  EXPECT_TRUE(has_error(r, "winds 2.000000 times")) << r.to_string();
  EXPECT_FALSE(has_error(r, "is not convex"));
}

TEST(Validate, VertexInFrontOfFace) {
  // A cube whose top is pushed in to a pyramid dent: planar, convex
  // triangles, but the top corners are in front of the dent's planes.
  std::vector<Vector3d> pts = test::box_points(Vector3d::Zero(), Vector3d::Ones());
  pts.push_back({0.5, 0.5, 0.5});
  auto polys = test::box_polygons();
  polys[kTop] = {4, 5, 8};
  polys.push_back({5, 6, 8});
  polys.push_back({6, 7, 8});
  polys.push_back({7, 4, 8});
  const HalfEdgeMesh m = test::mesh_from(pts, polys);
  const ValidationReport r = m.validate();
  EXPECT_TRUE(has_error(r, "in front of")) << r.to_string();
  EXPECT_FALSE(has_error(r, "off the face plane"));
  // Raised to a spike instead, the same polygons are a valid convex solid.
  pts[8].z() = 1.5;
  EXPECT_TRUE(test::mesh_from(pts, polys).validate().ok());
}

TEST(Validate, WrongWinding) {
  // A plane normal pointing against its face's winding.
  HalfEdgeMesh m = test::unit_cube();
  m.faces[kTop].plane.normal = -m.faces[kTop].plane.normal;
  m.faces[kTop].plane.offset = -m.faces[kTop].plane.offset;
  EXPECT_TRUE(has_error(m.validate(), "wound against its plane normal")) << m.validate().to_string();
  // A whole cube wound inside out (planes fitted to the reversed winding):
  // each face then has the rest of the cube in front of it.
  auto polys = test::box_polygons();
  for (auto& p : polys) std::reverse(p.begin(), p.end());
  const HalfEdgeMesh inside_out = test::mesh_from(test::box_points(Vector3d::Zero(), Vector3d::Ones()), polys);
  EXPECT_TRUE(has_error(inside_out.validate(), "in front of")) << inside_out.validate().to_string();
}

TEST(Validate, ToleranceDecidesNearlyPlanarFaces) {
  HalfEdgeMesh m = test::unit_cube();
  m.vertices[6].position.z() = 1.0 - 0.5 * m.tolerance();
  EXPECT_TRUE(m.validate().ok()) << m.validate().to_string();
  m.vertices[6].position.z() = 1.0 - 4 * m.tolerance();
  EXPECT_FALSE(m.validate().ok());
  EXPECT_TRUE(m.validate(8 * m.tolerance()).ok());
}

}  // namespace
}  // namespace hedra::hull
