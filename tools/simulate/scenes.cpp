// The scenes and their measures (see the header). Embedding hedra in Bullet
// takes three lines (marked "hedra:" below): a ShapeCache, a CreateFunc and
// register_hedra() on the dispatcher before the world steps; everything else
// is an ordinary Bullet world.
#include "simulate/scenes.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <memory>
#include <random>
#include <variant>
#include <vector>

#include "exact_reference.hpp"
#include "simulate/hedra_collision_algorithm.hpp"

namespace hedra::simulate {
namespace {

constexpr double kGravity = 9.81;
constexpr double kGroundHalfThickness = 0.5;  // the ground's top face is z = 0
constexpr double kExplosionSpeed = 20.0;      // m/s: nothing here falls fast enough to reach it

// Uniform in [lo, hi) from a 32-bit Mersenne twister, the same on every
// platform (std::uniform_real_distribution is not).
double uniform(std::mt19937& rng, double lo, double hi) { return lo + (hi - lo) * (rng() / 4294967296.0); }

// The shortest extent of a Bullet shape's local bounding box.
double bullet_size(const btCollisionShape& shape) {
  btVector3 lo, hi;
  shape.getAabb(btTransform::getIdentity(), lo, hi);
  const btVector3 d = hi - lo;
  return std::min({d.x(), d.y(), d.z()});
}

// The longest extent of a Bullet shape's local bounding box.
double bullet_width(const btCollisionShape& shape) {
  btVector3 lo, hi;
  shape.getAabb(btTransform::getIdentity(), lo, hi);
  const btVector3 d = hi - lo;
  return std::max({d.x(), d.y(), d.z()});
}

// One Bullet world with its bodies, torn down in the right order. Bodies are
// placed relative to the scene's origin (far from the world's for far-1e4/5).
class World {
 public:
  World(const SceneSettings& settings, const btVector3& ground_half_extents, const btVector3& origin, bool anchors)
      : dispatcher_(&configuration_),
        world_(&dispatcher_, &broadphase_, &solver_, &configuration_),
        origin_(origin),
        perturbation_(settings.perturbation),
        rng_(settings.seed * 7919u + 13u) {
    // hedra: every convex pair goes to hedra's contact(); other pairs keep
    // Bullet's algorithm.
    if (settings.bullet_merge) create_.update = ManifoldUpdate::bullet;
    if (settings.narrowphase == Narrowphase::hedra) register_hedra(dispatcher_, create_, shapes_);
    world_.setGravity(btVector3(0, 0, -kGravity));
    world_.getSolverInfo().m_numIterations = settings.solver_iterations;
    sleeping_ = settings.sleeping;
    anchors_ = anchors;
    ground_shape_ = std::make_unique<btBoxShape>(ground_half_extents);
    add(ground_shape_.get(), 0.0, btTransform(btQuaternion::getIdentity(), btVector3(0, 0, -ground_half_extents.z())));
  }
  ~World() {
    for (auto& body : bodies_) world_.removeRigidBody(body.get());
  }

  // Adds a body at `pose` from the scene's origin (mass 0: static; a dynamic
  // body's start perturbed); `shape` must outlive the world.
  btRigidBody* add(btCollisionShape* shape, double mass, const btTransform& pose) {
    btVector3 inertia(0, 0, 0);
    if (mass > 0.0) shape->calculateLocalInertia(mass, inertia);
    auto body = std::make_unique<btRigidBody>(mass, nullptr, shape, inertia);
    btTransform placed = pose;
    if (mass > 0.0 && perturbation_ > 0.0) {
      const double size = bullet_size(*shape);
      placed.setOrigin(pose.getOrigin() +
                       btVector3(uniform(rng_, -1, 1), uniform(rng_, -1, 1), 0) * perturbation_ * size);
      placed.setBasis(btMatrix3x3(btQuaternion(btVector3(0, 0, 1), uniform(rng_, -1, 1) * perturbation_)) *
                      pose.getBasis());
    }
    placed.setOrigin(placed.getOrigin() + origin_);
    body->setWorldTransform(placed);
    if (mass > 0.0) {
      if (!sleeping_) body->setActivationState(DISABLE_DEACTIVATION);
      if (anchors_) body->setCollisionFlags(body->getCollisionFlags() | btCollisionObject::CF_HAS_FRICTION_ANCHOR);
    }
    world_.addRigidBody(body.get());
    bodies_.push_back(std::move(body));
    return bodies_.back().get();
  }
  // hedra (and the measures) see `shape` for the Bullet shape `bullet`.
  void set_hedra_shape(const btCollisionShape* bullet, const CachedShape& shape) {
    shapes_.set(bullet, shape);
    measure_shapes_.set(bullet, shape);
  }

  btDiscreteDynamicsWorld& world() { return world_; }
  btCollisionDispatcher& dispatcher() { return dispatcher_; }
  const std::vector<std::unique_ptr<btRigidBody>>& bodies() const { return bodies_; }  // [0] is the ground
  // hedra's shape for a body (the measures use it with either narrowphase).
  const CachedShape* hedra_shape(const btRigidBody& body) { return measure_shapes_.get(body.getCollisionShape()); }

 private:
  btDefaultCollisionConfiguration configuration_;
  btCollisionDispatcher dispatcher_;
  HedraCollisionAlgorithm::CreateFunc create_;  // hedra: outlives the dispatcher's use of it
  ShapeCache shapes_;                           // hedra: the hedra shape of each Bullet shape
  btDbvtBroadphase broadphase_;
  btSequentialImpulseConstraintSolver solver_;
  btDiscreteDynamicsWorld world_;
  ShapeCache measure_shapes_;
  std::unique_ptr<btBoxShape> ground_shape_;
  std::vector<std::unique_ptr<btRigidBody>> bodies_;
  btVector3 origin_;
  double perturbation_;
  std::mt19937 rng_;
  bool sleeping_ = true;
  bool anchors_ = true;
};

// Shapes of the scene's dynamic bodies (they must outlive the world).
using ShapeList = std::vector<std::unique_ptr<btCollisionShape>>;

btTransform at(double x, double y, double z) { return btTransform(btQuaternion::getIdentity(), btVector3(x, y, z)); }

// `count` boxes of `half` half extents stacked from height `base`, the first of `first_mass` kg.
void build_box_stack(World& world, ShapeList& shapes, int count, const btVector3& half, double base = 0.0,
                     double first_mass = 1.0) {
  shapes.push_back(std::make_unique<btBoxShape>(half));
  for (int i = 0; i < count; ++i)
    world.add(shapes.back().get(), i == 0 ? first_mass : 1.0, at(0, 0, base + half.z() * (2 * i + 1)));
}

void build_pyramid(World& world, ShapeList& shapes) {
  shapes.push_back(std::make_unique<btBoxShape>(btVector3(0.5, 0.5, 0.5)));
  const double pitch = 1.02;  // 2 cm between neighbours in a row
  for (int level = 0; level < 4; ++level) {
    const int count = 4 - level;
    for (int i = 0; i < count; ++i) {
      const double x = (i - 0.5 * (count - 1)) * pitch;
      world.add(shapes.back().get(), 1.0, at(x, 0, 0.5 + level));
    }
  }
}

// A light box under a heavy one: a unit box of 1 kg, one of `heavy` kg on it.
void build_mass_ratio(World& world, ShapeList& shapes, double heavy) {
  shapes.push_back(std::make_unique<btBoxShape>(btVector3(0.5, 0.5, 0.5)));
  world.add(shapes.back().get(), 1.0, at(0, 0, 0.5));
  world.add(shapes.back().get(), heavy, at(0, 0, 1.5));
}

// A unit box on the ground, `shape` resting on it at `pose` (from the box's top).
void build_on_box(World& world, ShapeList& shapes, std::unique_ptr<btCollisionShape> shape, const btTransform& pose) {
  build_box_stack(world, shapes, 1, btVector3(0.5, 0.5, 0.5));
  btTransform placed = pose;
  placed.setOrigin(pose.getOrigin() + btVector3(0, 0, 1));
  world.add(shape.get(), 1.0, placed);
  shapes.push_back(std::move(shape));
}

// A unit vector, uniform on the sphere (rejection from the cube).
Eigen::Vector3d random_direction(std::mt19937& rng) {
  for (;;) {
    const Eigen::Vector3d v(uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1));
    const double n = v.norm();
    if (n > 0.1 && n <= 1.0) return v / n;
  }
}

struct PileLayout {
  int count = 20;
  int columns = 2, rows = 2;  // a layer of the grid
  double pitch = 1.2;         // between grid cells
  // Margins: < 0 Bullet's default (0.04); otherwise uniform in
  // [margin_lo, margin_hi) times the hull's smallest semi-axis doubled.
  double margin_lo = -1.0, margin_hi = -1.0;
};

void build_pile(World& world, ShapeList& shapes, unsigned seed, const PileLayout& layout) {
  std::mt19937 rng(seed);
  const int per_layer = layout.columns * layout.rows;
  for (int i = 0; i < layout.count; ++i) {
    const Eigen::Vector3d axes(uniform(rng, 0.25, 0.5), uniform(rng, 0.25, 0.5), uniform(rng, 0.25, 0.5));
    std::vector<Eigen::Vector3d> points;
    for (int k = 0; k < 12; ++k) points.push_back(random_direction(rng).cwiseProduct(axes));
    // Centre the points on the hull's centroid: Bullet puts the centre of
    // mass at the shape's origin.
    const auto built = collision::ConvexPolyhedron::build(points);
    const Eigen::Vector3d centroid = built.ok() ? built.polyhedron->offset() : Eigen::Vector3d::Zero();
    auto hull = std::make_unique<btConvexHullShape>();
    for (const Eigen::Vector3d& p : points) {
      const Eigen::Vector3d q = p - centroid;
      hull->addPoint(btVector3(q.x(), q.y(), q.z()), false);
    }
    hull->recalcLocalAabb();
    const Eigen::Vector3d axis = random_direction(rng);
    const double angle = uniform(rng, 0.0, 2.0 * M_PI);
    const btQuaternion rotation(btVector3(axis.x(), axis.y(), axis.z()), angle);
    const int column = i % layout.columns, row = (i / layout.columns) % layout.rows, layer = i / per_layer;
    const double x = (column - 0.5 * (layout.columns - 1)) * layout.pitch + uniform(rng, -0.1, 0.1);
    const double y = (row - 0.5 * (layout.rows - 1)) * layout.pitch + uniform(rng, -0.1, 0.1);
    if (layout.margin_lo >= 0.0) {
      hull->setMargin(uniform(rng, layout.margin_lo, layout.margin_hi) * 2.0 * axes.minCoeff());
      hull->recalcLocalAabb();
    }
    world.add(hull.get(), 1.0, btTransform(rotation, btVector3(x, y, 0.8 + layout.pitch * layer)));
    shapes.push_back(std::move(hull));
  }
}

// Five boxes of core half extent 0.45 rounded by 0.05: for Bullet the hull of
// the core's corners with that margin (its GJK rounds it), for hedra a Box
// with that margin.
void build_rounded_boxes(World& world, ShapeList& shapes) {
  const double core = 0.45, margin = 0.05;
  auto hull = std::make_unique<btConvexHullShape>();
  for (int i = 0; i < 8; ++i)
    hull->addPoint(btVector3(i & 1 ? core : -core, i & 2 ? core : -core, i & 4 ? core : -core), false);
  hull->setMargin(margin);
  hull->recalcLocalAabb();
  CachedShape rounded;
  rounded.shape = collision::Box{Eigen::Vector3d::Constant(core), margin};
  world.set_hedra_shape(hull.get(), rounded);
  for (int i = 0; i < 5; ++i) world.add(hull.get(), 1.0, at(0, 0, 0.5 + i));
  shapes.push_back(std::move(hull));
}

// Five hexagonal prisms (radius 0.45, 0.3 m core height) rounded by 0.05.
void build_rounded_hulls(World& world, ShapeList& shapes) {
  const double radius = 0.45, half = 0.15, margin = 0.05;
  auto hull = std::make_unique<btConvexHullShape>();
  for (int k = 0; k < 12; ++k) {
    const double angle = (k % 6) * M_PI / 3.0;
    hull->addPoint(btVector3(radius * std::cos(angle), radius * std::sin(angle), k < 6 ? -half : half), false);
  }
  hull->setMargin(margin);
  hull->recalcLocalAabb();
  const double height = 2.0 * (half + margin);
  for (int i = 0; i < 5; ++i) world.add(hull.get(), 1.0, at(0, 0, height * (i + 0.5)));
  shapes.push_back(std::move(hull));
}

// A rotation turning the body's z axis horizontal (along y).
btTransform lying(double z) { return btTransform(btQuaternion(btVector3(1, 0, 0), 0.5 * M_PI), btVector3(0, 0, z)); }

void build_curved(World& world, ShapeList& shapes, SceneKind scene) {
  switch (scene) {
    case SceneKind::capsule_lying:
      return build_on_box(world, shapes, std::make_unique<btCapsuleShapeZ>(0.2, 0.6), lying(0.2));
    case SceneKind::capsule_standing:
      return build_on_box(world, shapes, std::make_unique<btCapsuleShapeZ>(0.2, 0.6), at(0, 0, 0.5));
    case SceneKind::cylinder_lying:
      return build_on_box(world, shapes, std::make_unique<btCylinderShapeZ>(btVector3(0.3, 0.3, 0.4)), lying(0.3));
    case SceneKind::cylinder_standing:
      return build_on_box(world, shapes, std::make_unique<btCylinderShapeZ>(btVector3(0.3, 0.3, 0.4)), at(0, 0, 0.4));
    case SceneKind::cone_standing: {
      auto cone = std::make_unique<btConeShapeZ>(0.3, 0.8);
      cone->setMargin(0.01);
      return build_on_box(world, shapes, std::move(cone), at(0, 0, 0.41));
    }
    default:
      return build_on_box(world, shapes, std::make_unique<btSphereShape>(0.3), at(0, 0, 0.3));
  }
}

// What a scene needs besides its bodies.
struct SceneSpec {
  SceneKind kind;
  const char* name;
  double ground_half_side = 20.0;  // metres
  double distance = 0.0;           // of the scene's origin from the world's
  bool built = true;               // false for piles
  // Friction anchors (scenes.hpp): not under a curved body. An anchor holds
  // a contact point where it was, and a rolling sphere, capsule or cylinder
  // moves its point: with anchors (on either body of the pair) a sphere on
  // a box rolls off, its offset growing 14 times every 0.5 s, with either
  // narrowphase.
  bool anchors = true;
};

constexpr SceneSpec kScenes[] = {
    {SceneKind::stack, "stack"},
    {SceneKind::pyramid, "pyramid"},
    {SceneKind::pile, "pile", 20.0, 0.0, false},
    {SceneKind::stack_20, "stack-20"},
    {SceneKind::stack_30, "stack-30"},
    {SceneKind::mass_100, "mass-100"},
    {SceneKind::mass_1000, "mass-1000"},
    {SceneKind::plates, "plates"},
    {SceneKind::plate_1mm, "plate-1mm"},
    {SceneKind::pile_60, "pile-60", 20.0, 0.0, false},
    {SceneKind::pile_60_rounded, "pile-60-rounded", 20.0, 0.0, false},
    {SceneKind::far_1e4, "far-1e4", 20.0, 1e4},
    {SceneKind::far_1e5, "far-1e5", 20.0, 1e5},
    {SceneKind::tiny_on_ground, "tiny-on-ground", 50.0},
    {SceneKind::tiny_on_box, "tiny-on-box"},
    {SceneKind::rounded_boxes, "rounded-boxes"},
    {SceneKind::rounded_hulls, "rounded-hulls"},
    {SceneKind::capsule_lying, "capsule-lying", 20.0, 0.0, true, false},
    {SceneKind::capsule_standing, "capsule-standing", 20.0, 0.0, true, false},
    {SceneKind::cylinder_lying, "cylinder-lying", 20.0, 0.0, true, false},
    {SceneKind::cylinder_standing, "cylinder-standing", 20.0, 0.0, true, false},
    {SceneKind::cone_standing, "cone-standing", 20.0, 0.0, true, false},
    {SceneKind::sphere_on_box, "sphere-on-box", 20.0, 0.0, true, false},
};

const SceneSpec& spec(SceneKind scene) {
  for (const SceneSpec& s : kScenes)
    if (s.kind == scene) return s;
  return kScenes[0];
}

void build(World& world, ShapeList& shapes, const SceneSettings& settings) {
  const btVector3 tiny(0.01, 0.01, 0.01);
  PileLayout sixty;
  sixty.count = 60;
  sixty.columns = 3;
  sixty.rows = 4;
  sixty.pitch = 1.3;
  switch (settings.scene) {
    case SceneKind::stack:
    case SceneKind::far_1e4:
    case SceneKind::far_1e5:
      return build_box_stack(world, shapes, 10, btVector3(0.5, 0.5, 0.5));
    case SceneKind::stack_20:
      return build_box_stack(world, shapes, 20, btVector3(0.5, 0.5, 0.5));
    case SceneKind::stack_30:
      return build_box_stack(world, shapes, 30, btVector3(0.5, 0.5, 0.5));
    case SceneKind::pyramid:
      return build_pyramid(world, shapes);
    case SceneKind::pile:
      return build_pile(world, shapes, settings.seed, PileLayout{});
    case SceneKind::pile_60:
      sixty.margin_lo = sixty.margin_hi = 0.0;
      return build_pile(world, shapes, settings.seed, sixty);
    case SceneKind::pile_60_rounded:
      sixty.margin_lo = 0.02;
      sixty.margin_hi = 0.10;
      return build_pile(world, shapes, settings.seed, sixty);
    case SceneKind::mass_100:
      return build_mass_ratio(world, shapes, 100.0);
    case SceneKind::mass_1000:
      return build_mass_ratio(world, shapes, 1000.0);
    case SceneKind::plates:
      return build_box_stack(world, shapes, 10, btVector3(0.5, 0.5, 0.005));
    case SceneKind::plate_1mm:
      build_box_stack(world, shapes, 1, btVector3(0.5, 0.5, 0.5));
      return build_box_stack(world, shapes, 1, btVector3(0.25, 0.25, 0.0005), 1.0);
    case SceneKind::tiny_on_ground:
      return build_box_stack(world, shapes, 5, tiny);
    case SceneKind::tiny_on_box:
      build_box_stack(world, shapes, 1, btVector3(0.5, 0.5, 0.5));
      return build_box_stack(world, shapes, 5, tiny, 1.0);
    case SceneKind::rounded_boxes:
      return build_rounded_boxes(world, shapes);
    case SceneKind::rounded_hulls:
      return build_rounded_hulls(world, shapes);
    default:
      return build_curved(world, shapes, settings.scene);
  }
}

// The shortest extent of a body's shape in its own frame.
double body_size(const CachedShape& s) {
  struct Size {
    double operator()(const collision::Sphere& x) const { return 2.0 * (x.radius + x.margin); }
    double operator()(const collision::Box& x) const { return 2.0 * (x.half_extents.minCoeff() + x.margin); }
    double operator()(const collision::Capsule& x) const { return 2.0 * (x.radius + x.margin); }
    double operator()(const collision::Cylinder& x) const {
      return 2.0 * (std::min(x.radius, x.half_length) + x.margin);
    }
    double operator()(const collision::Cone& x) const { return 2.0 * (std::min(x.radius, x.half_length) + x.margin); }
    double operator()(const collision::Polyhedron& x) const {
      Eigen::Vector3d lo = Eigen::Vector3d::Constant(INFINITY), hi = -lo;
      for (const Eigen::Vector3d& v : x.hull->vertices()) {
        lo = lo.cwiseMin(v);
        hi = hi.cwiseMax(v);
      }
      return (hi - lo).minCoeff() + 2.0 * x.margin;
    }
  };
  return std::visit(Size{}, s.shape);
}

bool finite(const btVector3& v) { return std::isfinite(v.x()) && std::isfinite(v.y()) && std::isfinite(v.z()); }

// Whether two bodies' bounding boxes (Bullet's, margins included) meet.
bool boxes_meet(const btRigidBody& a, const btRigidBody& b) {
  btVector3 lo_a, hi_a, lo_b, hi_b;
  a.getCollisionShape()->getAabb(a.getWorldTransform(), lo_a, hi_a);
  b.getCollisionShape()->getAabb(b.getWorldTransform(), lo_b, hi_b);
  for (int k = 0; k < 3; ++k)
    if (hi_a[k] < lo_b[k] || hi_b[k] < lo_a[k]) return false;
  return true;
}

}  // namespace

const char* to_string(SceneKind scene) { return spec(scene).name; }

const char* to_string(Narrowphase narrowphase) { return narrowphase == Narrowphase::hedra ? "hedra" : "bullet"; }

bool parse(const std::string& name, SceneKind& scene) {
  for (const SceneSpec& s : kScenes)
    if (name == s.name) {
      scene = s.kind;
      return true;
    }
  return false;
}

bool parse(const std::string& name, Narrowphase& narrowphase) {
  for (const Narrowphase n : {Narrowphase::hedra, Narrowphase::bullet})
    if (name == to_string(n)) {
      narrowphase = n;
      return true;
    }
  return false;
}

std::vector<SceneKind> stiff_scenes() {
  std::vector<SceneKind> scenes;
  for (const SceneSpec& s : kScenes)
    if (s.kind > SceneKind::pile) scenes.push_back(s.kind);
  return scenes;
}

namespace {

// Steps the world, timing the steps and sampling speeds, contacts, NaN and
// explosions; fills the report's running measures.
void run_steps(World& world, const SceneSettings& settings, SceneReport& report, std::vector<btVector3>& at_halfway) {
  const auto& bodies = world.bodies();
  const int n = static_cast<int>(bodies.size());
  const int last_second = std::max(1, static_cast<int>(std::lround(settings.hz)));
  const int halfway = report.steps / 2;
  std::vector<double> step_us;
  step_us.reserve(report.steps);
  double speed_squares = 0.0;
  long speed_samples = 0, manifolds = 0, points = 0;
  const double dt = 1.0 / settings.hz;
  for (int step = 0; step < report.steps; ++step) {
    // Steps with every body asleep cost almost nothing: time the others.
    bool awake = false;
    for (int i = 1; i < n; ++i) awake = awake || bodies[i]->isActive();
    const auto start = std::chrono::steady_clock::now();
    world.world().stepSimulation(dt, 1, dt);
    const auto stop = std::chrono::steady_clock::now();
    if (awake) step_us.push_back(std::chrono::duration<double, std::micro>(stop - start).count());
    btCollisionDispatcher& dispatcher = world.dispatcher();
    for (int m = 0; m < dispatcher.getNumManifolds(); ++m) {
      const int count = dispatcher.getManifoldByIndexInternal(m)->getNumContacts();
      if (count > 0) {
        ++manifolds;
        points += count;
      }
    }
    for (int i = 1; i < n; ++i) {
      const btVector3& v = bodies[i]->getLinearVelocity();
      if (!finite(bodies[i]->getWorldTransform().getOrigin()) || !finite(v)) report.non_finite = true;
      if (v.length() > kExplosionSpeed) report.exploded = true;
      if (step + 1 == halfway) at_halfway[i] = bodies[i]->getWorldTransform().getOrigin();
      if (step >= report.steps - last_second) {
        speed_squares += v.length2();
        ++speed_samples;
      }
    }
  }
  report.points_per_manifold = manifolds > 0 ? static_cast<double>(points) / manifolds : 0.0;
  report.manifolds_per_step = static_cast<double>(manifolds) / report.steps;
  if (!step_us.empty()) {
    std::nth_element(step_us.begin(), step_us.begin() + step_us.size() / 2, step_us.end());
    report.median_step_us = step_us[step_us.size() / 2];
  }
  report.jitter = speed_samples > 0 ? std::sqrt(speed_squares / speed_samples) : 0.0;
}

// Final state, measured for either narrowphase by the exact reference
// (tools/reference: qhull's hull of the Minkowski difference, independent of
// hedra's GJK/EPA/SAT) between every pair of bodies whose bounding boxes
// meet (no other pair can overlap), on the same rounded shapes Bullet sees.
void measure_end(World& world, const std::vector<btTransform>& starts, const std::vector<btVector3>& at_halfway,
                 SceneReport& report) {
  const auto& bodies = world.bodies();
  const int n = static_cast<int>(bodies.size());
  std::vector<const CachedShape*> hedra_shapes(n);
  std::vector<double> sizes(n), widths(n);  // smallest and largest extents
  report.size = INFINITY;
  report.lowest_above_ground = INFINITY;
  report.stands = report.built;
  for (int i = 0; i < n; ++i) {
    hedra_shapes[i] = world.hedra_shape(*bodies[i]);
    sizes[i] = hedra_shapes[i] ? body_size(*hedra_shapes[i]) : 0.0;
    widths[i] = bullet_width(*bodies[i]->getCollisionShape());
    if (i == 0) continue;
    const btTransform& end = bodies[i]->getWorldTransform();
    report.size = std::min(report.size, sizes[i]);
    report.late_creep = std::max(report.late_creep, static_cast<double>((end.getOrigin() - at_halfway[i]).length()));
    report.max_speed = std::max(report.max_speed, static_cast<double>(bodies[i]->getLinearVelocity().length()));
    if (!bodies[i]->isActive()) ++report.asleep;
    const btVector3 moved = end.getOrigin() - starts[i].getOrigin();
    const double turned = end.getRotation().angleShortestPath(starts[i].getRotation());
    if (!(std::hypot(moved.x(), moved.y()) < 0.25 * widths[i] && turned < 0.2)) report.stands = false;
  }
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < n; ++j) {
      if (!hedra_shapes[i] || !hedra_shapes[j] || !boxes_meet(*bodies[i], *bodies[j])) continue;
      const reference::ExactResult r = reference::exact_signed_distance(
          hedra_shapes[i]->shape, hedra_shapes[i]->pose(bodies[i]->getWorldTransform()), hedra_shapes[j]->shape,
          hedra_shapes[j]->pose(bodies[j]->getWorldTransform()));
      if (!r.ok) {
        report.measure_failures++;
        continue;
      }
      const double size = i == 0 ? sizes[j] : std::min(sizes[i], sizes[j]);
      report.max_penetration = std::max(report.max_penetration, -r.distance / size);
      if (i == 0) report.lowest_above_ground = std::min(report.lowest_above_ground, r.distance / size);
    }
}

}  // namespace

SceneReport run_scene(const SceneSettings& settings) {
  const SceneSpec& scene = spec(settings.scene);
  const btVector3 origin = btVector3(1, 1, 1) * (scene.distance / std::sqrt(3.0));
  ShapeList shapes;  // declared before the world: destroyed after it
  World world(settings, btVector3(scene.ground_half_side, scene.ground_half_side, kGroundHalfThickness), origin,
              settings.anchors && scene.anchors);
  build(world, shapes, settings);
  const auto& bodies = world.bodies();
  const int n = static_cast<int>(bodies.size());

  SceneReport report;
  report.bodies = n - 1;
  report.built = scene.built;
  report.steps = std::max(1, static_cast<int>(std::lround(settings.seconds * settings.hz)));
  int top = 1;
  for (int i = 1; i < n; ++i)
    if (bodies[i]->getWorldTransform().getOrigin().z() > bodies[top]->getWorldTransform().getOrigin().z()) top = i;
  std::vector<btTransform> starts(n);
  std::vector<btVector3> at_halfway(n);
  for (int i = 0; i < n; ++i) {
    starts[i] = bodies[i]->getWorldTransform();
    at_halfway[i] = starts[i].getOrigin();
  }
  const long queries_before = HedraCollisionAlgorithm::queries();
  run_steps(world, settings, report, at_halfway);
  report.hedra_queries = HedraCollisionAlgorithm::queries() - queries_before;
  measure_end(world, starts, at_halfway, report);
  if (scene.built) {
    const btVector3 d = bodies[top]->getWorldTransform().getOrigin() - starts[top].getOrigin();
    report.top_drift = std::hypot(d.x(), d.y());
    const CachedShape* top_shape = world.hedra_shape(*bodies[top]);
    report.top_size = top_shape ? body_size(*top_shape) : 0.0;
  }
  return report;
}

}  // namespace hedra::simulate
