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
#include <vector>

#include "exact_reference.hpp"
#include "simulate/hedra_collision_algorithm.hpp"

namespace hedra::simulate {
namespace {

constexpr double kGravity = 9.81;
constexpr double kGroundHalfThickness = 0.5;  // the ground's top face is z = 0

// One Bullet world with its bodies, torn down in the right order.
class World {
 public:
  World(Narrowphase narrowphase, const SceneSettings& settings)
      : dispatcher_(&configuration_), world_(&dispatcher_, &broadphase_, &solver_, &configuration_) {
    // hedra: box-box, box-hull, hull-box and hull-hull pairs go to hedra's
    // contact(); every other pair keeps Bullet's algorithm.
    if (narrowphase == Narrowphase::hedra) register_hedra(dispatcher_, create_, shapes_);
    world_.setGravity(btVector3(0, 0, -kGravity));
    world_.getSolverInfo().m_numIterations = settings.solver_iterations;
    sleeping_ = settings.sleeping;
    anchors_ = settings.anchors;
    ground_shape_ = std::make_unique<btBoxShape>(btVector3(20, 20, kGroundHalfThickness));
    add(ground_shape_.get(), 0.0, btTransform(btQuaternion::getIdentity(), btVector3(0, 0, -kGroundHalfThickness)));
  }
  ~World() {
    for (auto& body : bodies_) world_.removeRigidBody(body.get());
  }

  // Adds a body (mass 0: static); `shape` must outlive the world.
  btRigidBody* add(btCollisionShape* shape, double mass, const btTransform& pose) {
    btVector3 inertia(0, 0, 0);
    if (mass > 0.0) shape->calculateLocalInertia(mass, inertia);
    auto body = std::make_unique<btRigidBody>(mass, nullptr, shape, inertia);
    body->setWorldTransform(pose);
    if (mass > 0.0) {
      if (!sleeping_) body->setActivationState(DISABLE_DEACTIVATION);
      if (anchors_) body->setCollisionFlags(body->getCollisionFlags() | btCollisionObject::CF_HAS_FRICTION_ANCHOR);
    }
    world_.addRigidBody(body.get());
    bodies_.push_back(std::move(body));
    return bodies_.back().get();
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
  bool sleeping_ = true;
  bool anchors_ = true;
};

// Shapes of the scene's dynamic bodies (they must outlive the world).
using ShapeList = std::vector<std::unique_ptr<btCollisionShape>>;

// Uniform in [lo, hi) from a 32-bit Mersenne twister, the same on every
// platform (std::uniform_real_distribution is not).
double uniform(std::mt19937& rng, double lo, double hi) { return lo + (hi - lo) * (rng() / 4294967296.0); }

void build_stack(World& world, ShapeList& shapes) {
  shapes.push_back(std::make_unique<btBoxShape>(btVector3(0.5, 0.5, 0.5)));
  for (int i = 0; i < 10; ++i)
    world.add(shapes.back().get(), 1.0, btTransform(btQuaternion::getIdentity(), btVector3(0, 0, 0.5 + i)));
}

void build_pyramid(World& world, ShapeList& shapes) {
  shapes.push_back(std::make_unique<btBoxShape>(btVector3(0.5, 0.5, 0.5)));
  const double pitch = 1.02;  // 2 cm between neighbours in a row
  for (int level = 0; level < 4; ++level) {
    const int count = 4 - level;
    for (int i = 0; i < count; ++i) {
      const double x = (i - 0.5 * (count - 1)) * pitch;
      world.add(shapes.back().get(), 1.0, btTransform(btQuaternion::getIdentity(), btVector3(x, 0, 0.5 + level)));
    }
  }
}

// A unit vector, uniform on the sphere (rejection from the cube).
Eigen::Vector3d random_direction(std::mt19937& rng) {
  for (;;) {
    const Eigen::Vector3d v(uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1));
    const double n = v.norm();
    if (n > 0.1 && n <= 1.0) return v / n;
  }
}

void build_pile(World& world, ShapeList& shapes, unsigned seed) {
  std::mt19937 rng(seed);
  for (int i = 0; i < 20; ++i) {
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
    const int layer = i / 4;
    const double x = ((i % 2) - 0.5) * 1.2 + uniform(rng, -0.1, 0.1);
    const double y = (((i / 2) % 2) - 0.5) * 1.2 + uniform(rng, -0.1, 0.1);
    world.add(hull.get(), 1.0, btTransform(rotation, btVector3(x, y, 0.8 + 1.2 * layer)));
    shapes.push_back(std::move(hull));
  }
}

// The shortest extent of a body's shape in its own frame.
double body_size(const CachedShape& s) {
  if (const auto* box = std::get_if<collision::Box>(&s.shape)) return 2.0 * box->half_extents.minCoeff();
  const auto& poly = std::get<collision::Polyhedron>(s.shape);
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(INFINITY), hi = -lo;
  for (const Eigen::Vector3d& v : poly.hull->vertices()) {
    lo = lo.cwiseMin(v);
    hi = hi.cwiseMax(v);
  }
  return (hi - lo).minCoeff() + 2.0 * poly.margin;
}

}  // namespace

const char* to_string(SceneKind scene) {
  switch (scene) {
    case SceneKind::stack:
      return "stack";
    case SceneKind::pyramid:
      return "pyramid";
    case SceneKind::pile:
      return "pile";
  }
  return "?";
}

const char* to_string(Narrowphase narrowphase) { return narrowphase == Narrowphase::hedra ? "hedra" : "bullet"; }

bool parse(const std::string& name, SceneKind& scene) {
  for (const SceneKind s : {SceneKind::stack, SceneKind::pyramid, SceneKind::pile})
    if (name == to_string(s)) {
      scene = s;
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

SceneReport run_scene(const SceneSettings& settings) {
  ShapeList shapes;  // declared before the world: destroyed after it
  World world(settings.narrowphase, settings);
  switch (settings.scene) {
    case SceneKind::stack:
      build_stack(world, shapes);
      break;
    case SceneKind::pyramid:
      build_pyramid(world, shapes);
      break;
    case SceneKind::pile:
      build_pile(world, shapes, settings.seed);
      break;
  }
  const auto& bodies = world.bodies();
  const int n = static_cast<int>(bodies.size());

  SceneReport report;
  report.bodies = n - 1;
  report.steps = std::max(1, static_cast<int>(std::lround(settings.seconds * settings.hz)));
  const int last_second = std::max(1, static_cast<int>(std::lround(settings.hz)));
  const int halfway = report.steps / 2;
  int top = 1;
  for (int i = 1; i < n; ++i)
    if (bodies[i]->getWorldTransform().getOrigin().z() > bodies[top]->getWorldTransform().getOrigin().z()) top = i;
  const btVector3 top_start = bodies[top]->getWorldTransform().getOrigin();
  std::vector<btVector3> at_halfway(n);
  for (int i = 0; i < n; ++i) at_halfway[i] = bodies[i]->getWorldTransform().getOrigin();

  std::vector<double> step_us;
  step_us.reserve(report.steps);
  double speed_squares = 0.0;
  long speed_samples = 0, manifolds = 0, points = 0;
  const long queries_before = HedraCollisionAlgorithm::queries();
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
    if (step + 1 == halfway)
      for (int i = 1; i < n; ++i) at_halfway[i] = bodies[i]->getWorldTransform().getOrigin();
    if (step >= report.steps - last_second)
      for (int i = 1; i < n; ++i) {
        speed_squares += bodies[i]->getLinearVelocity().length2();
        ++speed_samples;
      }
  }
  report.hedra_queries = HedraCollisionAlgorithm::queries() - queries_before;
  report.points_per_manifold = manifolds > 0 ? static_cast<double>(points) / manifolds : 0.0;
  report.manifolds_per_step = static_cast<double>(manifolds) / report.steps;
  if (!step_us.empty()) {
    std::nth_element(step_us.begin(), step_us.begin() + step_us.size() / 2, step_us.end());
    report.median_step_us = step_us[step_us.size() / 2];
  }
  report.jitter = speed_samples > 0 ? std::sqrt(speed_squares / speed_samples) : 0.0;
  if (settings.scene != SceneKind::pile) {
    const btVector3 d = bodies[top]->getWorldTransform().getOrigin() - top_start;
    report.top_drift = std::hypot(d.x(), d.y());
  }

  // Final state, measured for either narrowphase by the exact reference
  // (tools/reference: qhull's hull of the Minkowski difference, independent
  // of hedra's GJK/EPA/SAT) between every pair of bodies, on the same
  // rounded shapes Bullet sees.
  std::vector<const CachedShape*> hedra_shapes(n);
  std::vector<double> sizes(n);
  report.size = INFINITY;
  report.lowest_above_ground = INFINITY;
  for (int i = 0; i < n; ++i) {
    hedra_shapes[i] = world.hedra_shape(*bodies[i]);
    sizes[i] = hedra_shapes[i] ? body_size(*hedra_shapes[i]) : 0.0;
    if (i > 0) {
      report.size = std::min(report.size, sizes[i]);
      const btVector3 d = bodies[i]->getWorldTransform().getOrigin() - at_halfway[i];
      report.late_creep = std::max(report.late_creep, static_cast<double>(d.length()));
      report.max_speed = std::max(report.max_speed, static_cast<double>(bodies[i]->getLinearVelocity().length()));
      if (!bodies[i]->isActive()) ++report.asleep;
    }
  }
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < n; ++j) {
      if (!hedra_shapes[i] || !hedra_shapes[j]) continue;
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
  return report;
}

}  // namespace hedra::simulate
