// hedra_mujoco's runs and exact distances (measure.hpp).
#include "mujoco/measure.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <set>
#include <utility>

namespace hedra::mujoco {

namespace {

void to_stderr_warning(const char* message) { std::fprintf(stderr, "MuJoCo warning: %s\n", message); }
void to_stderr_error(const char* message) {
  std::fprintf(stderr, "MuJoCo error: %s\n", message);
  std::exit(3);
}

bool is_free(const mjModel* m, int body) {
  const int joint = m->body_jntadr[body];
  return m->body_jntnum[body] >= 1 && joint >= 0 && m->jnt_type[joint] == mjJNT_FREE;
}

bool state_finite(const mjModel* m, const mjData* d) {
  for (int i = 0; i < m->nq; ++i)
    if (!std::isfinite(d->qpos[i])) return false;
  for (int i = 0; i < m->nv; ++i)
    if (!std::isfinite(d->qvel[i])) return false;
  return d->warning[mjWARN_BADQACC].number == 0;
}

}  // namespace

void route_messages_to_stderr() {
  mju_user_warning = to_stderr_warning;
  mju_user_error = to_stderr_error;
}

mjModel* load_model(const std::string& path, std::string* error) {
  char message[1024] = "";
  mjModel* m = mj_loadXML(path.c_str(), nullptr, message, sizeof message);
  if (m == nullptr && error) *error = message[0] ? message : "MuJoCo could not load the model";
  return m;
}

const char* to_string(Engine engine) {
  switch (engine) {
    case Engine::hedra:
      return "hedra";
    case Engine::mujoco:
      return "mujoco";
    case Engine::mujoco_multiccd:
      return "mujoco-multiccd";
  }
  return "unknown";
}

RunResult run(mjModel* m, Engine engine, double seconds, std::string* error) {
  RunResult out;
  out.narrowphase = to_string(engine);
  const int flags = m->opt.enableflags;
  if (engine == Engine::mujoco_multiccd) m->opt.enableflags |= mjENBL_MULTICCD;
  if (engine == Engine::mujoco) m->opt.enableflags &= ~mjENBL_MULTICCD;
  std::unique_ptr<Narrowphase> hedra;
  if (engine == Engine::hedra) {
    hedra = Narrowphase::install(m, error);
    if (!hedra) return out;
    out.hulls_built = hedra->hulls_built();
  }
  mjData* d = mj_makeData(m);
  if (m->nkey > 0) mj_resetDataKeyframe(m, d, 0);
  mj_forward(m, d);
  std::vector<int> bodies;
  std::vector<Eigen::Vector3d> start;
  for (int b = 1; b < m->nbody; ++b)
    if (is_free(m, b)) bodies.push_back(b), start.emplace_back(d->xpos[3 * b], d->xpos[3 * b + 1], d->xpos[3 * b + 2]);
  out.steps = static_cast<int>(std::lround(seconds / m->opt.timestep));
  std::vector<double> times(out.steps);
  long contacts = 0;
  for (int s = 0; s < out.steps; ++s) {
    const auto t0 = std::chrono::steady_clock::now();
    mj_step(m, d);
    times[s] = std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - t0).count();
    contacts += d->ncon;
    if (!state_finite(m, d)) out.nan = true;
    for (std::size_t i = 0; i < bodies.size(); ++i) {
      const Eigen::Vector3d moved = Eigen::Map<const Eigen::Vector3d>(d->xpos + 3 * bodies[i]) - start[i];
      if (!moved.allFinite()) continue;
      out.max_drift = std::max(out.max_drift, moved.head<2>().norm());
      out.max_displacement = std::max(out.max_displacement, moved.norm());
    }
  }
  out.mean_contacts = out.steps > 0 ? static_cast<double>(contacts) / out.steps : 0.0;
  if (!times.empty()) {
    std::nth_element(times.begin(), times.begin() + times.size() / 2, times.end());
    out.step_us = times[times.size() / 2];
  }
  hedra.reset();  // the exact reference measures MuJoCo's state, not hedra's
  out.max_penetration = out.nan ? 0.0 : ExactGeometry(m).max_penetration(d);
  mj_deleteData(d);
  m->opt.enableflags = flags;
  return out;
}

ExactGeometry::ExactGeometry(const mjModel* m) : m_(m), hulls_(m->nmesh), points_(m->nmesh) {
  for (int mesh = 0; mesh < m->nmesh; ++mesh) {
    points_[mesh] = mesh_points(m, mesh);
    auto built = collision::ConvexPolyhedron::build(points_[mesh]);
    if (built.ok()) hulls_[mesh] = built.polyhedron;
  }
}

double ExactGeometry::size(int g) const {
  const auto shape = shape_of(m_, g, hulls_);
  if (!shape) return 0.0;
  double radius = collision::bounding_radius(*shape);
  if (const auto* poly = std::get_if<collision::Polyhedron>(&*shape)) radius += poly->hull->offset().norm();
  return radius;
}

reference::ExactResult ExactGeometry::pair(const mjData* d, int g1, int g2) const {
  const auto b = shape_of(m_, g2, hulls_);
  if (!b) return {};
  reference::ExactSettings settings;
  const int mesh_b = m_->geom_dataid[g2];
  if (m_->geom_type[g2] == mjGEOM_MESH) settings.override_b = &points_[mesh_b];
  const collision::Pose pose_b = geom_pose(d, g2);
  if (m_->geom_type[g1] == mjGEOM_PLANE) {
    const collision::Pose plane = geom_pose(d, g1);
    const Eigen::Vector3d n = plane.rotation.col(2);
    const double above = n.dot(pose_b.translation - plane.translation);
    const double L = 100.0 * size(g2) + std::abs(above) + 1.0;
    collision::Pose box_pose{plane.rotation, pose_b.translation - (above + L) * n};
    return reference::exact_signed_distance(collision::Box{Eigen::Vector3d::Constant(L), 0.0}, box_pose, *b, pose_b,
                                            settings);
  }
  const auto a = shape_of(m_, g1, hulls_);
  if (!a) return {};
  if (m_->geom_type[g1] == mjGEOM_MESH) settings.override_a = &points_[m_->geom_dataid[g1]];
  return reference::exact_signed_distance(*a, geom_pose(d, g1), *b, pose_b, settings);
}

reference::ExactResult ExactGeometry::point(const mjData* d, int g, const Eigen::Vector3d& x) const {
  if (m_->geom_type[g] == mjGEOM_PLANE) {
    const collision::Pose plane = geom_pose(d, g);
    reference::ExactResult r;
    r.ok = true;
    r.distance = plane.rotation.col(2).dot(x - plane.translation);
    r.error_bound = 1e-15 * (x - plane.translation).norm();
    return r;
  }
  const auto shape = shape_of(m_, g, hulls_);
  if (!shape) return {};
  reference::ExactSettings settings;
  if (m_->geom_type[g] == mjGEOM_MESH) settings.override_b = &points_[m_->geom_dataid[g]];
  return reference::exact_signed_distance(collision::Sphere{0.0, 0.0}, collision::Pose::from_translation(x), *shape,
                                          geom_pose(d, g), settings);
}

double ExactGeometry::max_penetration(const mjData* d) const {
  std::set<std::pair<int, int>> pairs;
  for (int i = 0; i < d->ncon; ++i) pairs.insert({d->contact[i].geom1, d->contact[i].geom2});
  double deepest = 0.0;
  for (const auto& [g1, g2] : pairs) {
    const reference::ExactResult r = pair(d, g1, g2);
    if (r.ok) deepest = std::max(deepest, -r.distance);
  }
  return deepest;
}

}  // namespace hedra::mujoco
