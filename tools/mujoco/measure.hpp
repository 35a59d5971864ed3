// What hedra_mujoco measures, apart from the program so the tests use it too:
// a run of a model with one narrowphase, and exact distances (tools/reference,
// independent of hedra's queries) between a model's geoms.
//
// The exact reference knows no planes: a plane stands there as a box far
// larger than the other geom (100 times its bounding radius, plus its
// distance to the plane) whose top face is the plane, under that geom; exact
// while the geom lies over the box's top face. Meshes go to the reference as
// MuJoCo's own vertices (not hedra's hull of them).
#pragma once

#include <mujoco/mujoco.h>

#include <Eigen/Core>
#include <exact_reference.hpp>
#include <memory>
#include <string>
#include <vector>

#include "mujoco/hedra_mujoco.hpp"

namespace hedra::mujoco {

// MuJoCo's warnings and errors on stderr (its default prints them on stdout
// and writes MUJOCO_LOG.TXT); an error then exits with status 3.
void route_messages_to_stderr();

// mj_loadXML, its message in `error` when it fails.
mjModel* load_model(const std::string& path, std::string* error);

enum class Engine { hedra, mujoco, mujoco_multiccd };
const char* to_string(Engine engine);

struct RunResult {
  std::string narrowphase;
  int steps = 0;
  double max_drift = 0.0;
  double max_displacement = 0.0;
  double max_penetration = 0.0;
  double mean_contacts = 0.0;
  double step_us = 0.0;
  bool nan = false;
  int hulls_built = 0;  // hedra runs
};

// Runs `m` for `seconds` from its first keyframe (or qpos0). The model's
// multiccd flag is set for the run and restored after; hedra is installed for
// a hedra run and uninstalled after (`error` set if it cannot be).
RunResult run(mjModel* m, Engine engine, double seconds, std::string* error);

// The exact geometry of a model's geoms (hulls of the meshes for the
// Polyhedron shapes the reference wants, with MuJoCo's vertices as points).
class ExactGeometry {
 public:
  explicit ExactGeometry(const mjModel* m);
  // Signed distance of geoms g1 and g2 at d's poses (planes: g1).
  reference::ExactResult pair(const mjData* d, int g1, int g2) const;
  // Signed distance of a world point to geom g's surface (< 0 inside).
  reference::ExactResult point(const mjData* d, int g, const Eigen::Vector3d& x) const;
  // A size for tolerances: geom g's bounding radius (0 for planes).
  double size(int g) const;
  // The largest depth among the geom pairs of d's contacts (0 if none).
  double max_penetration(const mjData* d) const;

 private:
  const mjModel* m_;
  std::vector<std::shared_ptr<const collision::ConvexPolyhedron>> hulls_;
  std::vector<std::vector<Eigen::Vector3d>> points_;  // MuJoCo's vertices by mesh
};

}  // namespace hedra::mujoco
