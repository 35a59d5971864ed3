// hedra as MuJoCo's convex narrowphase: pair functions installed into
// mjCOLLISIONFUNC (mujoco/mujoco.h) for one model, and taken out again.
//
//   auto hedra = hedra::mujoco::Narrowphase::install(model, &error);
//   ... mj_step(model, data) ...      // hedra answers the pairs below
//   hedra.reset();                    // MuJoCo's own functions again
//
// Pairs hedra answers (MuJoCo orders every pair so that type[g1] <=
// type[g2]): every plane pair (the plane as a Halfspace: z <= 0 in the
// geom's frame), box-box, and every pair with a cylinder or a mesh, i.e.
// everything MuJoCo 2.x sends to libccd's MPR plus the ground and box-box.
// MuJoCo keeps: ellipsoids and height fields (hedra has no ellipsoid, and a
// height field is not convex), and its closed forms among spheres, capsules
// and boxes (exact already; capsule-capsule and capsule-box give two points
// for parallel pairs, where hedra's curved pairs give one).
//
// Conventions (MuJoCo's, each tested in tests/mujoco): contact `dist` the
// signed distance (< 0 penetration) = -hedra's depth; `pos` the midpoint of
// the two surfaces along the normal (hedra's point); frame[0..2] the unit
// normal from geom1 toward geom2 (hedra's A = geom1), frame[3..8] zero (the
// driver builds the tangents, as for MuJoCo's own functions); every point
// with dist < margin, margin as the driver passes it (hedra's contact
// distance; MuJoCo's gap is applied by the driver; hedra's shape margins
// stay zero: a geom's MuJoCo margin is not a rounding of its shape). Box
// size = half extents; capsule and cylinder along local z, size = (radius,
// half-length); poses from geom_xpos and the row-major geom_xmat.
//
// Meshes: the hull of each mesh's vertices (mesh_vert, in the geom's frame)
// is built once, at install, and shared by every geom using that mesh. Per
// call nothing is allocated: shapes are built at install, each pair's
// ContactCache lives in a direct-mapped table made at install. MuJoCo
// stores mesh vertices as floats, turned into the mesh's inertial frame: a
// cube's square faces are then planar only to float precision, and a hull
// built to double precision splits each into two triangles (a face contact
// on a triangle keeps 3 of the square's 4 corners). By default the hull is
// built with the tolerance of MuJoCo's floats (8 FLT_EPSILON of the mesh's
// largest coordinate), which merges them; contacts are then exact to within
// that tolerance of MuJoCo's vertices. InstallOptions::exact_hulls builds
// them to double precision: exact to MuJoCo's vertices within 1e-9 of the size.
//
// Geom types, sizes and meshes are read at install: install again after
// changing them in the model. The table is global, so install() and reset()
// must not run while another thread steps. A model that was not installed gets MuJoCo's saved function.
// MuJoCo 2.2 to 3.8 keep this callback (3.0 adds a geom type: the table is
// sized from mjNGEOMTYPES); 3.9 changed it.
#pragma once

#include <mujoco/mujoco.h>

#include <Eigen/Core>
#include <cstdint>
#include <hedra/collision/halfspace.hpp>
#include <hedra/collision/manifold.hpp>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace hedra::mujoco {

// Does hedra answer pairs of these MuJoCo geom types (in either order)?
bool hedra_answers(int type1, int type2);

// The hedra shape of geom g of a MuJoCo model (nullopt for planes, height
// fields and ellipsoids); meshes from `hulls` (one per mesh id, may be null).
std::optional<collision::Shape> shape_of(const mjModel* m, int g,
                                         const std::vector<std::shared_ptr<const collision::ConvexPolyhedron>>& hulls);

// The pose of geom g in d (geom_xpos, row-major geom_xmat).
collision::Pose geom_pose(const mjData* d, int g);

// The mesh's vertices (geom frame), as MuJoCo stores them.
std::vector<Eigen::Vector3d> mesh_points(const mjModel* m, int mesh);

struct NarrowphaseStats {
  std::uint64_t calls = 0;     // pair calls hedra answered
  std::uint64_t contacts = 0;  // contacts returned
  std::uint64_t failures = 0;  // calls whose status was not ok (points kept when finite)
};

struct InstallOptions {
  bool exact_hulls = false;  // hulls to double precision, not to MuJoCo's floats (see the top of the file)
};

// The hull tolerance of a mesh whose largest |coordinate| is `reach`.
double float_hull_tolerance(double reach);

class Narrowphase {
 public:
  // Builds the shapes and hulls of `m` and installs hedra's pair functions.
  // Null with `error` set when a mesh's hull cannot be built or 16 models
  // are installed already.
  static std::unique_ptr<Narrowphase> install(const mjModel* m, std::string* error = nullptr,
                                              const InstallOptions& options = {});
  ~Narrowphase();  // uninstalls (MuJoCo's functions back once no model is installed)
  Narrowphase(const Narrowphase&) = delete;
  Narrowphase& operator=(const Narrowphase&) = delete;

  const mjModel* model() const { return model_; }
  // How many hulls install() built (one per mesh used by a collision geom).
  int hulls_built() const { return hulls_built_; }
  // The largest tolerance a hull was built with (0 with exact_hulls).
  double hull_tolerance() const { return hull_tolerance_; }
  const std::vector<std::shared_ptr<const collision::ConvexPolyhedron>>& hulls() const { return hulls_; }
  // hedra's shape for geom g (null for planes and geoms MuJoCo keeps).
  const collision::Shape* shape(int g) const;
  const NarrowphaseStats& stats() const { return stats_; }
  collision::ContactSettings& settings() { return settings_; }

  // The pair function: what mjCOLLISIONFUNC calls for this model.
  int collide(const mjData* d, mjContact* con, int g1, int g2, mjtNum margin);

 private:
  explicit Narrowphase(const mjModel* m) : model_(m) {}
  collision::ContactCache& cache(int g1, int g2);

  struct CacheSlot {
    int g1 = -1, g2 = -1;
    collision::ContactCache cache;
  };
  const mjModel* model_;
  std::vector<std::optional<collision::Shape>> shapes_;
  std::vector<std::shared_ptr<const collision::ConvexPolyhedron>> hulls_;  // by mesh id
  std::vector<CacheSlot> caches_;                                          // power-of-two size
  collision::ContactSettings settings_;
  NarrowphaseStats stats_;
  int hulls_built_ = 0;
  double hull_tolerance_ = 0.0;
};

}  // namespace hedra::mujoco
