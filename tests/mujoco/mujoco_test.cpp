// hedra as MuJoCo's narrowphase (tools/mujoco/hedra_mujoco.hpp): MuJoCo's
// contact conventions one by one, every contact's depth against the exact
// reference (tools/reference, MuJoCo's own mesh vertices), hulls built once
// and nothing allocated per step, install and uninstall, scenes that stand,
// and the hedra_mujoco program's output and exit codes.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <memory>
#include <sstream>
#include <string>

#include "../collision/allocation_counter.hpp"
#include "mujoco/hedra_mujoco.hpp"
#include "mujoco/measure.hpp"

namespace hedra::mujoco {
namespace {

using Vec = Eigen::Vector3d;

struct ModelDeleter {
  void operator()(mjModel* m) const { mj_deleteModel(m); }
};
struct DataDeleter {
  void operator()(mjData* d) const { mj_deleteData(d); }
};
using ModelPtr = std::unique_ptr<mjModel, ModelDeleter>;
using DataPtr = std::unique_ptr<mjData, DataDeleter>;

ModelPtr load_string(const std::string& xml) {
  char error[1000] = "";
  mjVFS vfs;
  mj_defaultVFS(&vfs);
  mj_makeEmptyFileVFS(&vfs, "model.xml", static_cast<int>(xml.size()));
  const int file = mj_findFileVFS(&vfs, "model.xml");
  std::copy(xml.begin(), xml.end(), static_cast<char*>(vfs.filedata[file]));
  mjModel* m = mj_loadXML("model.xml", &vfs, error, sizeof error);
  mj_deleteVFS(&vfs);
  EXPECT_NE(m, nullptr) << error;
  return ModelPtr(m);
}

ModelPtr load_scene(const std::string& name) {
  std::string error;
  mjModel* m = load_model(std::string(HEDRA_MUJOCO_SCENES) + "/" + name + ".xml", &error);
  EXPECT_NE(m, nullptr) << error;
  return ModelPtr(m);
}

const char* kCube =
    "-0.05 -0.05 -0.05 0.05 -0.05 -0.05 -0.05 0.05 -0.05 0.05 0.05 -0.05 "
    "-0.05 -0.05 0.05 0.05 -0.05 0.05 -0.05 0.05 0.05 0.05 0.05 0.05";

// One geom `body_geom` in a free body at `pos` / `quat` over a plane.
std::string on_plane(const std::string& body_geom, const std::string& pos, const std::string& quat = "1 0 0 0",
                     const std::string& extra = "") {
  return std::string("<mujoco><asset><mesh name=\"cube\" vertex=\"") + kCube +
         "\"/></asset><worldbody><geom name=\"floor\" type=\"plane\" size=\"1 1 0.1\" " + extra + "/><body pos=\"" +
         pos + "\" quat=\"" + quat + "\"><freejoint/>" + body_geom + "</body></worldbody></mujoco>";
}

TEST(MujocoConventions, MeshCubeSunkIntoThePlaneGivesFourContactsWithDistPosAndNormal) {
  ModelPtr m = load_string(on_plane("<geom type=\"mesh\" mesh=\"cube\"/>", "0.3 -0.2 0.049"));
  auto hedra = Narrowphase::install(m.get());
  ASSERT_TRUE(hedra);
  DataPtr d(mj_makeData(m.get()));
  mj_forward(m.get(), d.get());
  ASSERT_EQ(d->ncon, 4);
  for (int i = 0; i < d->ncon; ++i) {
    const mjContact& c = d->contact[i];
    EXPECT_EQ(c.geom1, 0);  // the plane: MuJoCo orders the pair by type
    EXPECT_EQ(c.geom2, 1);
    // MuJoCo stores mesh vertices as floats, recentred on the mesh's
    // centroid: the corners are where they were within a few 1e-9.
    EXPECT_NEAR(c.dist, -0.001, 1e-8);                  // signed distance, negative: penetration
    EXPECT_NEAR(c.pos[2], -0.0005, 1e-8);               // midway between z = 0 and the corner at -0.001
    EXPECT_NEAR(std::abs(c.pos[0] - 0.3), 0.05, 1e-8);  // the bottom corners
    EXPECT_NEAR(std::abs(c.pos[1] + 0.2), 0.05, 1e-8);
    // Exactly: geom1.s witness (pos - dist/2 normal) on the plane.
    EXPECT_NEAR(c.pos[2] - c.dist / 2.0, 0.0, 1e-18);
    EXPECT_EQ(Vec(c.frame[0], c.frame[1], c.frame[2]), Vec::UnitZ());  // from geom1 toward geom2
    // MuJoCo's driver made the tangents of hedra's frame: orthonormal.
    const Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> frame(c.frame);
    EXPECT_LT((frame * frame.transpose() - Eigen::Matrix3d::Identity()).norm(), 1e-12);
  }
  // The pair function itself: frame[3..8] zero, the geoms named.
  mjContact con[mjMAXCONPAIR];
  ASSERT_EQ(hedra->collide(d.get(), con, 0, 1, 0.0), 4);
  for (int i = 0; i < 4; ++i)
    for (int k = 3; k < 9; ++k) EXPECT_EQ(con[i].frame[k], 0.0);
}

TEST(MujocoConventions, BoxSizeIsHalfExtentsAndPosesComeFromTheRowMajorMatrix) {
  // A box of half extents (0.1, 0.2, 0.3) turned 90 degrees about x: its
  // local y (0.2) is vertical, so at height 0.199 it is 0.001 deep.
  ModelPtr m = load_string(on_plane("<geom type=\"box\" size=\"0.1 0.2 0.3\"/>", "0 0 0.199",
                                    "0.70710678118654757 0.70710678118654757 0 0"));
  auto hedra = Narrowphase::install(m.get());
  DataPtr d(mj_makeData(m.get()));
  mj_forward(m.get(), d.get());
  ASSERT_EQ(d->ncon, 4);
  for (int i = 0; i < 4; ++i) {
    EXPECT_NEAR(d->contact[i].dist, -0.001, 1e-12);
    EXPECT_NEAR(std::abs(d->contact[i].pos[1]), 0.3, 1e-12);  // local z (0.3) along world y
    EXPECT_NEAR(std::abs(d->contact[i].pos[0]), 0.1, 1e-12);
  }
}

TEST(MujocoConventions, CapsuleAndCylinderRunAlongLocalZWithSizeRadiusAndHalfLength) {
  // Standing: a capsule (0.05, 0.2) reaches 0.25 below its centre; a cylinder 0.2.
  ModelPtr m = load_string(on_plane("<geom type=\"capsule\" size=\"0.05 0.2\"/>", "0 0 0.248"));
  auto hedra = Narrowphase::install(m.get());
  DataPtr d(mj_makeData(m.get()));
  mj_forward(m.get(), d.get());
  ASSERT_EQ(d->ncon, 1);
  EXPECT_NEAR(d->contact[0].dist, -0.002, 1e-12);
  hedra.reset();
  m = load_string(on_plane("<geom type=\"cylinder\" size=\"0.05 0.2\"/>", "0 0 0.198"));
  hedra = Narrowphase::install(m.get());
  d.reset(mj_makeData(m.get()));
  mj_forward(m.get(), d.get());
  ASSERT_EQ(d->ncon, 4);  // the bottom cap's rim on +-x, +-y
  for (int i = 0; i < 4; ++i) {
    EXPECT_NEAR(d->contact[i].dist, -0.002, 1e-12);
    EXPECT_NEAR(std::hypot(d->contact[i].pos[0], d->contact[i].pos[1]), 0.05, 1e-12);
  }
}

TEST(MujocoConventions, EveryPointWithDistBelowTheMarginIsReturned) {
  // The cube 0.005 above the plane: margin 0.01 reports its four corners at
  // dist 0.005; margin 0.004 none. hedra's shape margins stay zero.
  for (const double margin : {0.01, 0.004}) {
    ModelPtr m = load_string(
        on_plane("<geom type=\"mesh\" mesh=\"cube\" margin=\"" + std::to_string(margin) + "\"/>", "0 0 0.055"));
    auto hedra = Narrowphase::install(m.get());
    EXPECT_EQ(std::get<collision::Polyhedron>(*hedra->shape(1)).margin, 0.0);
    DataPtr d(mj_makeData(m.get()));
    mj_forward(m.get(), d.get());
    ASSERT_EQ(d->ncon, margin > 0.005 ? 4 : 0) << margin;
    for (int i = 0; i < d->ncon; ++i) EXPECT_NEAR(d->contact[i].dist, 0.005, 1e-8);  // float vertices
  }
}

TEST(MujocoConventions, NormalsPointFromGeom1TowardGeom2) {
  ModelPtr m = load_scene("stack_3");
  auto hedra = Narrowphase::install(m.get());
  DataPtr d(mj_makeData(m.get()));
  for (int s = 0; s < 50; ++s) mj_step(m.get(), d.get());
  ASSERT_GT(d->ncon, 8);
  for (int i = 0; i < d->ncon; ++i) {
    const mjContact& c = d->contact[i];
    const Vec between =
        Eigen::Map<const Vec>(d->geom_xpos + 3 * c.geom2) - Eigen::Map<const Vec>(d->geom_xpos + 3 * c.geom1);
    if (m->geom_type[c.geom1] == mjGEOM_PLANE) {
      EXPECT_GT(c.frame[2], 0.999);
    } else {
      EXPECT_GT(Vec(c.frame[0], c.frame[1], c.frame[2]).dot(between), 0.0);
    }
  }
}

// Every contact hedra gives: its two witnesses (pos -+ dist/2 normal) lie on
// the two geoms' surfaces, so dist is the gap along the normal there. The
// pair's deepest dist is the exact signed distance, or, where hedra's
// manifold keeps a face normal within its bias (manifold.hpp) rather than
// the exact normal, deeper (never shallower) by at most that bias.
// With exact_hulls, exact to MuJoCo's float vertices; by default within
// the hulls' float tolerance of them (hedra_mujoco.hpp).
void expect_exact_contacts(const char* scene, int steps, bool exact_hulls = true) {
  ModelPtr m = load_scene(scene);
  InstallOptions options;
  options.exact_hulls = exact_hulls;
  auto hedra = Narrowphase::install(m.get(), nullptr, options);
  const double hull_tolerance = hedra->hull_tolerance();
  EXPECT_EQ(hull_tolerance == 0.0, exact_hulls);
  DataPtr d(mj_makeData(m.get()));
  for (int s = 0; s < steps; ++s) mj_step(m.get(), d.get());
  mj_forward(m.get(), d.get());  // contacts at the final poses
  ASSERT_GT(d->ncon, 0);
  const ExactGeometry exact(m.get());
  std::map<std::pair<int, int>, double> deepest;
  for (int i = 0; i < d->ncon; ++i) {
    const mjContact& c = d->contact[i];
    const Vec pos(c.pos[0], c.pos[1], c.pos[2]), n(c.frame[0], c.frame[1], c.frame[2]);
    const double size = std::max(exact.size(c.geom1), exact.size(c.geom2));
    const reference::ExactResult on1 = exact.point(d.get(), c.geom1, pos - (c.dist / 2.0) * n);
    const reference::ExactResult on2 = exact.point(d.get(), c.geom2, pos + (c.dist / 2.0) * n);
    ASSERT_TRUE(on1.ok && on2.ok);
    EXPECT_NEAR(on1.distance, 0.0, 1e-9 * size + hull_tolerance + on1.error_bound) << scene << " contact " << i;
    EXPECT_NEAR(on2.distance, 0.0, 1e-9 * size + hull_tolerance + on2.error_bound) << scene << " contact " << i;
    auto [it, fresh] = deepest.insert({{c.geom1, c.geom2}, c.dist});
    if (!fresh) it->second = std::min(it->second, c.dist);
  }
  for (const auto& [pair, dist] : deepest) {
    const reference::ExactResult r = exact.pair(d.get(), pair.first, pair.second);
    ASSERT_TRUE(r.ok) << r.reason;
    const double size = std::max(exact.size(pair.first), exact.size(pair.second));
    const double tol = 1e-9 * size + 2.0 * hull_tolerance + r.error_bound;
    const collision::ContactSettings settings;
    const double bias = settings.relative_bias * std::abs(r.distance) + settings.absolute_bias * size;
    EXPECT_LE(dist, r.distance + tol) << scene << " geoms " << pair.first << " " << pair.second;
    EXPECT_GE(dist, r.distance - bias - tol) << scene << " geoms " << pair.first << " " << pair.second;
    if (std::abs(dist - r.distance) > tol)
      std::printf("%s geoms %d %d: deepest dist %.17g, exact %.17g (a face normal within the bias)\n", scene,
                  pair.first, pair.second, dist, r.distance);
  }
}

TEST(MujocoExact, StackOfMeshCubes) { expect_exact_contacts("stack_5", 200); }
TEST(MujocoExact, CylinderOnABox) { expect_exact_contacts("cylinder_on_box", 200); }
TEST(MujocoExact, CapsuleOnAMeshSlab) { expect_exact_contacts("capsule_on_slab", 200); }
TEST(MujocoExact, ThinMeshBoxYawedOnABox) { expect_exact_contacts("thin_box_yawed", 200); }
TEST(MujocoExact, PileOfMeshRocks) { expect_exact_contacts("rocks_30", 300); }
TEST(MujocoExact, StackOfMeshCubesWithinTheFloatToleranceOfTheDefaultHulls) {
  expect_exact_contacts("stack_5", 200, false);
}
TEST(MujocoExact, PileOfMeshRocksWithinTheFloatToleranceOfTheDefaultHulls) {
  expect_exact_contacts("rocks_30", 300, false);
}

// The reason for the float tolerance: MuJoCo's cube, turned into its
// inertial frame in floats, keeps square faces (four points a resting face)
// only with it.
TEST(MujocoMeshes, FloatToleranceKeepsACubesSquareFaces) {
  ModelPtr m = load_scene("stack_3");
  auto merged = Narrowphase::install(m.get());
  const auto& cube = std::get<collision::Polyhedron>(*merged->shape(1));
  EXPECT_EQ(cube.hull->mesh().face_count(), 6u);
  merged.reset();
  InstallOptions exact;
  exact.exact_hulls = true;
  auto split = Narrowphase::install(m.get(), nullptr, exact);
  EXPECT_GT(std::get<collision::Polyhedron>(*split->shape(1)).hull->mesh().face_count(), 6u);
}

TEST(MujocoMeshes, HullsAreBuiltOncePerMeshSharedAndNothingIsAllocatedPerStep) {
  ModelPtr m = load_scene("rocks_30");  // 6 meshes, 30 geoms
  auto hedra = Narrowphase::install(m.get());
  EXPECT_EQ(hedra->hulls_built(), 6);
  for (int g = 0; g < m->ngeom; ++g) {
    if (m->geom_type[g] != mjGEOM_MESH) continue;
    const auto& poly = std::get<collision::Polyhedron>(*hedra->shape(g));
    EXPECT_EQ(poly.hull.get(), hedra->hulls()[m->geom_dataid[g]].get());
  }
  DataPtr d(mj_makeData(m.get()));
  for (int s = 0; s < 100; ++s) mj_step(m.get(), d.get());  // the pile starts touching
  const std::uint64_t calls = hedra->stats().calls;
  const long before = g_allocations.load();
  for (int s = 0; s < 100; ++s) mj_step(m.get(), d.get());
  EXPECT_EQ(g_allocations.load(), before);
  EXPECT_GT(hedra->stats().calls, calls + 1000);
  EXPECT_GT(hedra->stats().contacts, 0u);
  EXPECT_EQ(hedra->stats().failures, 0u);
}

TEST(MujocoInstall, UninstallGivesMuJoCosFunctionsBackAndOtherModelsKeepThem) {
  const mjfCollision own = mjCOLLISIONFUNC[mjGEOM_PLANE][mjGEOM_MESH];
  const mjfCollision box_box = mjCOLLISIONFUNC[mjGEOM_BOX][mjGEOM_BOX];
  const mjfCollision sphere_sphere = mjCOLLISIONFUNC[mjGEOM_SPHERE][mjGEOM_SPHERE];
  ModelPtr a = load_string(on_plane("<geom type=\"mesh\" mesh=\"cube\"/>", "0 0 0.049"));
  ModelPtr b = load_string(on_plane("<geom type=\"mesh\" mesh=\"cube\"/>", "0 0 0.049"));
  {
    auto hedra = Narrowphase::install(a.get());
    EXPECT_NE(mjCOLLISIONFUNC[mjGEOM_PLANE][mjGEOM_MESH], own);
    EXPECT_NE(mjCOLLISIONFUNC[mjGEOM_BOX][mjGEOM_BOX], box_box);
    EXPECT_EQ(mjCOLLISIONFUNC[mjGEOM_SPHERE][mjGEOM_SPHERE], sphere_sphere);  // MuJoCo's closed form stays
    EXPECT_FALSE(Narrowphase::install(a.get()));                              // once per model
    DataPtr da(mj_makeData(a.get())), db(mj_makeData(b.get()));
    mj_forward(a.get(), da.get());
    mj_forward(b.get(), db.get());
    EXPECT_EQ(da->ncon, 4);
    // b is not installed: MuJoCo's own plane-mesh function answers it.
    mjContact con[mjMAXCONPAIR];
    EXPECT_EQ(db->ncon, own(b.get(), db.get(), con, 0, 1, 0.0));
  }
  EXPECT_EQ(mjCOLLISIONFUNC[mjGEOM_PLANE][mjGEOM_MESH], own);
  EXPECT_EQ(mjCOLLISIONFUNC[mjGEOM_BOX][mjGEOM_BOX], box_box);
}

TEST(MujocoInstall, PairsHedraAnswersAndPairsMuJoCoKeeps) {
  EXPECT_TRUE(hedra_answers(mjGEOM_PLANE, mjGEOM_MESH));
  EXPECT_TRUE(hedra_answers(mjGEOM_PLANE, mjGEOM_SPHERE));
  EXPECT_TRUE(hedra_answers(mjGEOM_BOX, mjGEOM_BOX));
  EXPECT_TRUE(hedra_answers(mjGEOM_CYLINDER, mjGEOM_CAPSULE));
  EXPECT_TRUE(hedra_answers(mjGEOM_MESH, mjGEOM_SPHERE));
  EXPECT_FALSE(hedra_answers(mjGEOM_PLANE, mjGEOM_PLANE));
  EXPECT_FALSE(hedra_answers(mjGEOM_ELLIPSOID, mjGEOM_MESH));
  EXPECT_FALSE(hedra_answers(mjGEOM_HFIELD, mjGEOM_BOX));
  EXPECT_FALSE(hedra_answers(mjGEOM_CAPSULE, mjGEOM_BOX));
}

TEST(MujocoScenes, StackOfTenMeshCubesStandsWithoutNaN) {
  ModelPtr m = load_scene("stack_10");
  std::string error;
  const RunResult r = run(m.get(), Engine::hedra, 2.0, &error);
  EXPECT_TRUE(error.empty()) << error;
  EXPECT_FALSE(r.nan);
  EXPECT_LT(r.max_drift, 1e-3);
  EXPECT_LT(r.max_penetration, 5e-3);
  EXPECT_EQ(r.steps, 1000);
}

TEST(MujocoScenes, HeldMeshBoxDoesNotSlip) {
  ModelPtr m = load_scene("gripper");
  std::string error;
  const RunResult r = run(m.get(), Engine::hedra, 2.0, &error);
  EXPECT_FALSE(r.nan);
  EXPECT_LT(r.max_displacement, 1e-5);
}

#ifdef HEDRA_MUJOCO_PROGRAM
struct Output {
  int status = -1;
  std::string out, err;
};

Output run_program(const std::string& arguments) {
  const std::string base = ::testing::TempDir() + "hedra_mujoco_test";
  const std::string command =
      std::string(HEDRA_MUJOCO_PROGRAM) + " " + arguments + " > " + base + ".out 2> " + base + ".err";
  Output o;
  const int raw = std::system(command.c_str());
  o.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
  std::stringstream out, err;
  out << std::ifstream(base + ".out").rdbuf();
  err << std::ifstream(base + ".err").rdbuf();
  o.out = out.str();
  o.err = err.str();
  return o;
}

TEST(MujocoProgram, BadOrMissingModelExitsTwoWithMuJoCosMessageAndNothingOnStdout) {
  const Output broken = run_program(std::string(HEDRA_MUJOCO_TEST_DATA) + "/broken.xml --json");
  EXPECT_EQ(broken.status, 2);
  EXPECT_TRUE(broken.out.empty()) << broken.out;
  EXPECT_NE(broken.err.find("XML parse error"), std::string::npos) << broken.err;  // MuJoCo's words
  const Output missing = run_program("/nonexistent/model.xml");
  EXPECT_EQ(missing.status, 2);
  EXPECT_TRUE(missing.out.empty());
  EXPECT_NE(missing.err.find("nonexistent"), std::string::npos) << missing.err;
}

TEST(MujocoProgram, JsonHasTheModelAndOneRunPerNarrowphaseWithExactlyTheFields) {
  const Output o =
      run_program(std::string(HEDRA_MUJOCO_SCENES) + "/stack_3.xml --seconds 0.2 --narrowphase both --multiccd --json");
  ASSERT_EQ(o.status, 0) << o.err;
  for (const char* field :
       {"\"model\"", "\"runs\"", "\"narrowphase\": \"hedra\"", "\"narrowphase\": \"mujoco-multiccd\"", "\"steps\": 100",
        "\"max_drift\"", "\"max_displacement\"", "\"max_penetration\"", "\"mean_contacts\"", "\"step_us\"",
        "\"nan\": false"})
    EXPECT_NE(o.out.find(field), std::string::npos) << field << "\n" << o.out;
  std::size_t fields = 0;
  for (std::size_t at = o.out.find("\": "); at != std::string::npos; at = o.out.find("\": ", at + 1)) ++fields;
  EXPECT_EQ(fields, 2u + 2u * 8u);  // "model", "runs", then 8 fields per run
}
#endif

}  // namespace
}  // namespace hedra::mujoco
