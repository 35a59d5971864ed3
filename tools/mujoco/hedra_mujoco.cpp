// hedra's pair functions in MuJoCo's mjCOLLISIONFUNC (hedra_mujoco.hpp).
//
// One pair function for every entry hedra answers; it finds the model's
// Narrowphase in a small registry (a linear scan of at most 16 pointers)
// and otherwise calls the function MuJoCo had there. MuJoCo's table is
// saved when the first model is installed and written back when the last
// one is uninstalled.
#include "mujoco/hedra_mujoco.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace hedra::mujoco {

namespace {

constexpr int kMaxModels = 16;
std::array<Narrowphase*, kMaxModels> g_installed{};
int g_installed_count = 0;
mjfCollision g_saved[mjNGEOMTYPES][mjNGEOMTYPES];

Narrowphase* find(const mjModel* m) {
  for (Narrowphase* n : g_installed)
    if (n != nullptr && n->model() == m) return n;
  return nullptr;
}

int pair_function(const mjModel* m, const mjData* d, mjContact* con, int g1, int g2, mjtNum margin) {
  if (Narrowphase* n = find(m)) return n->collide(d, con, g1, g2, margin);
  const mjfCollision own = g_saved[m->geom_type[g1]][m->geom_type[g2]];
  return own != nullptr ? own(m, d, con, g1, g2, margin) : 0;
}

bool convex(int type) {
  return type == mjGEOM_SPHERE || type == mjGEOM_CAPSULE || type == mjGEOM_CYLINDER || type == mjGEOM_BOX ||
         type == mjGEOM_MESH;
}

}  // namespace

bool hedra_answers(int type1, int type2) {
  const int lo = std::min(type1, type2), hi = std::max(type1, type2);
  if (lo == mjGEOM_PLANE) return convex(hi);  // plane-plane: MuJoCo collides no planes either
  if (!convex(lo) || !convex(hi)) return false;
  return (lo == mjGEOM_BOX && hi == mjGEOM_BOX) || lo == mjGEOM_CYLINDER || hi == mjGEOM_CYLINDER ||
         lo == mjGEOM_MESH || hi == mjGEOM_MESH;
}

std::optional<collision::Shape> shape_of(const mjModel* m, int g,
                                         const std::vector<std::shared_ptr<const collision::ConvexPolyhedron>>& hulls) {
  const mjtNum* size = m->geom_size + 3 * g;
  switch (m->geom_type[g]) {
    case mjGEOM_SPHERE:
      return collision::Sphere{size[0], 0.0};
    case mjGEOM_CAPSULE:
      return collision::Capsule{size[0], size[1], 0.0};
    case mjGEOM_CYLINDER:
      return collision::Cylinder{size[0], size[1], 0.0};
    case mjGEOM_BOX:
      return collision::Box{Eigen::Vector3d(size[0], size[1], size[2]), 0.0};
    case mjGEOM_MESH: {
      const int mesh = m->geom_dataid[g];
      if (mesh < 0 || mesh >= static_cast<int>(hulls.size()) || !hulls[mesh]) return std::nullopt;
      return collision::Polyhedron{hulls[mesh], 0.0};
    }
    default:
      return std::nullopt;
  }
}

collision::Pose geom_pose(const mjData* d, int g) {
  collision::Pose pose;
  pose.rotation = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(d->geom_xmat + 9 * g);
  pose.translation = Eigen::Map<const Eigen::Vector3d>(d->geom_xpos + 3 * g);
  return pose;
}

std::vector<Eigen::Vector3d> mesh_points(const mjModel* m, int mesh) {
  std::vector<Eigen::Vector3d> points(m->mesh_vertnum[mesh]);
  const float* v = m->mesh_vert + 3 * m->mesh_vertadr[mesh];
  for (std::size_t i = 0; i < points.size(); ++i) points[i] = {v[3 * i], v[3 * i + 1], v[3 * i + 2]};
  return points;
}

double float_hull_tolerance(double reach) { return 8.0 * std::numeric_limits<float>::epsilon() * reach; }

std::unique_ptr<Narrowphase> Narrowphase::install(const mjModel* m, std::string* error, const InstallOptions& options) {
  const auto fail = [&](const std::string& message) {
    if (error) *error = message;
    return std::unique_ptr<Narrowphase>();
  };
  if (m == nullptr) return fail("no model");
  if (find(m) != nullptr) return fail("this model is installed already");
  if (g_installed_count == kMaxModels) return fail("16 models are installed already");
  std::unique_ptr<Narrowphase> n(new Narrowphase(m));
  // The hulls of the meshes that collision geoms use, once per mesh.
  n->hulls_.resize(m->nmesh);
  for (int g = 0; g < m->ngeom; ++g) {
    const int mesh = m->geom_dataid[g];
    if (m->geom_type[g] != mjGEOM_MESH || mesh < 0 || n->hulls_[mesh]) continue;
    if (m->geom_contype[g] == 0 && m->geom_conaffinity[g] == 0) continue;  // visual only
    const std::vector<Eigen::Vector3d> points = mesh_points(m, mesh);
    hull::QuickhullOptions hull_options;
    if (!options.exact_hulls) {
      double reach = 0.0;
      for (const Eigen::Vector3d& p : points) reach = std::max(reach, p.cwiseAbs().maxCoeff());
      hull_options.tolerance = float_hull_tolerance(reach);
      n->hull_tolerance_ = std::max(n->hull_tolerance_, hull_options.tolerance);
    }
    auto built = collision::ConvexPolyhedron::build(points, hull_options);
    if (!built.ok()) return fail("mesh " + std::to_string(mesh) + ": " + built.message);
    n->hulls_[mesh] = built.polyhedron;
    ++n->hulls_built_;
  }
  n->shapes_.reserve(m->ngeom);
  for (int g = 0; g < m->ngeom; ++g) n->shapes_.push_back(shape_of(m, g, n->hulls_));
  std::size_t slots = 64;
  while (slots < 4 * static_cast<std::size_t>(m->ngeom) && slots < (1u << 16)) slots *= 2;
  n->caches_.resize(slots);

  if (g_installed_count == 0) {
    for (int i = 0; i < mjNGEOMTYPES; ++i)
      for (int j = 0; j < mjNGEOMTYPES; ++j) g_saved[i][j] = mjCOLLISIONFUNC[i][j];
    for (int i = 0; i < mjNGEOMTYPES; ++i)
      for (int j = i; j < mjNGEOMTYPES; ++j)
        if (hedra_answers(i, j)) mjCOLLISIONFUNC[i][j] = pair_function;
  }
  *std::find(g_installed.begin(), g_installed.end(), nullptr) = n.get();
  ++g_installed_count;
  return n;
}

Narrowphase::~Narrowphase() {
  auto slot = std::find(g_installed.begin(), g_installed.end(), this);
  if (slot == g_installed.end()) return;
  *slot = nullptr;
  if (--g_installed_count == 0) {
    for (int i = 0; i < mjNGEOMTYPES; ++i)
      for (int j = 0; j < mjNGEOMTYPES; ++j) mjCOLLISIONFUNC[i][j] = g_saved[i][j];
  }
}

const collision::Shape* Narrowphase::shape(int g) const {
  if (g < 0 || g >= static_cast<int>(shapes_.size()) || !shapes_[g]) return nullptr;
  return &*shapes_[g];
}

collision::ContactCache& Narrowphase::cache(int g1, int g2) {
  const std::uint32_t hash = static_cast<std::uint32_t>(g1) * 73856093u ^ static_cast<std::uint32_t>(g2) * 19349663u;
  CacheSlot& slot = caches_[hash & (caches_.size() - 1)];
  if (slot.g1 != g1 || slot.g2 != g2) slot = CacheSlot{g1, g2, {}};  // another pair had it: start cold
  return slot.cache;
}

int Narrowphase::collide(const mjData* d, mjContact* con, int g1, int g2, mjtNum margin) {
  ++stats_.calls;
  const collision::Shape* b = shape(g2);
  if (b == nullptr) return 0;
  const collision::Pose pose_a = geom_pose(d, g1), pose_b = geom_pose(d, g2);
  collision::ContactSettings settings = settings_;
  settings.contact_distance = std::max(0.0, margin);
  collision::ContactCache& pair_cache = cache(g1, g2);
  collision::ContactResult r;
  if (model_->geom_type[g1] == mjGEOM_PLANE) {
    r = collision::contact(collision::Halfspace{}, pose_a, *b, pose_b, &pair_cache, settings);
  } else {
    const collision::Shape* a = shape(g1);
    if (a == nullptr) return 0;
    r = collision::contact(*a, pose_a, *b, pose_b, &pair_cache, settings);
  }
  if (r.status != collision::Status::ok) ++stats_.failures;
  if (r.status == collision::Status::invalid_input || r.status == collision::Status::degenerate) return 0;
  int count = 0;
  for (int k = 0; k < r.count && count < mjMAXCONPAIR; ++k) {
    const collision::ContactPoint& p = r.points[k];
    const double dist = -p.depth;
    if (!(dist < margin) || !p.point.allFinite()) continue;  // MuJoCo's rule: dist < margin
    mjContact& c = con[count++];
    c.dist = dist;
    for (int i = 0; i < 3; ++i) c.pos[i] = p.point[i], c.frame[i] = r.normal[i];
    for (int i = 3; i < 9; ++i) c.frame[i] = 0.0;
    c.geom1 = g1;
    c.geom2 = g2;
  }
  stats_.contacts += count;
  return count;
}

}  // namespace hedra::mujoco
