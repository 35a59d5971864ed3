// The example of docs/continuous.md, compiled and checked: the code between
// the markers is the page's, character for character.
#include <gtest/gtest.h>

#include <cstdio>
#include <hedra/collision/query.hpp>

// --- example begins ---
#include <Eigen/Geometry>
#include <hedra/collision/cast.hpp>
#include <hedra/collision/raycast.hpp>
#include <hedra/collision/time_of_impact.hpp>

using namespace hedra::collision;

struct ExampleAnswers {
  RaycastResult ray;
  CastResult cast, toi;
  Sweep box_sweep;  // to check the answer afterwards
};

ExampleAnswers continuous_example() {
  // A plate 4 m x 4 m, 1 cm thick, its top face at z = 0.
  const Box plate{Eigen::Vector3d(2.0, 2.0, 0.005), 0.0};
  const Pose plate_pose = Pose::from_translation(Eigen::Vector3d(0.0, 0.0, -0.005));
  ExampleAnswers out;

  // A picking ray from 3 m above, straight down, 10 m long: it hits the top
  // face at 3 m, fraction 0.3 of the ray.
  out.ray = raycast(plate, plate_pose, Eigen::Vector3d(0.5, 0.0, 3.0), Eigen::Vector3d(0.0, 0.0, -10.0));
  std::printf("ray:  %s at %.6f, normal (%g, %g, %g)\n", to_string(out.ray.status), out.ray.fraction,
              out.ray.normal.x(), out.ray.normal.y(), out.ray.normal.z());

  // A character's capsule (radius 0.3 m, axis 1 m long) swept 2 m down from
  // 1.5 m: its lowest point, 0.7 m up, reaches the plate at t = 0.35.
  const Capsule character{0.3, 0.5, 0.0};
  const Pose start = Pose::from_translation(Eigen::Vector3d(0.0, 0.0, 1.5));
  out.cast = shape_cast(character, start, Eigen::Vector3d(0.0, 0.0, -2.0), plate, plate_pose, Eigen::Vector3d::Zero());
  std::printf("cast: %s at %.6f, distance %.1e, normal (%g, %g, %g)\n", to_string(out.cast.status), out.cast.fraction,
              out.cast.distance, out.cast.normal.x(), out.cast.normal.y(), out.cast.normal.z());

  // A 10 cm box at 200 m/s over a 1/60 s step, spinning 3 rad about x: it
  // would pass through the plate between two frames. Its time of impact is
  // never after the first contact.
  const Box bullet{Eigen::Vector3d(0.05, 0.05, 0.05), 0.0};
  const Pose from = Pose::from_translation(Eigen::Vector3d(0.0, 0.0, 1.0));
  const Pose to = Pose::from_quaternion(Eigen::Quaterniond(Eigen::AngleAxisd(3.0, Eigen::Vector3d::UnitX())),
                                        Eigen::Vector3d(0.0, 0.0, 1.0 - 200.0 / 60.0));
  out.box_sweep = {from, to};
  const Sweep still{plate_pose, plate_pose};
  out.toi = time_of_impact(bullet, out.box_sweep, plate, still);
  std::printf("toi:  %s at %.6f after %d steps\n", to_string(out.toi.status), out.toi.fraction, out.toi.iterations);
  return out;
}
// --- example ends ---

namespace {

TEST(ContinuousExample, AnswersWhatThePageSays) {
  const ExampleAnswers a = continuous_example();
  ASSERT_EQ(a.ray.status, CastStatus::hit);
  EXPECT_NEAR(a.ray.fraction, 0.3, 1e-15);
  EXPECT_EQ(a.ray.normal, Eigen::Vector3d(0, 0, 1));

  ASSERT_EQ(a.cast.status, CastStatus::hit);
  EXPECT_NEAR(a.cast.fraction, 0.35, 1e-10);
  EXPECT_NEAR(a.cast.distance, 0.0, 1e-10);
  EXPECT_NEAR((a.cast.normal - Eigen::Vector3d(0, 0, -1)).norm(), 0.0, 1e-9);  // A (capsule) toward B (plate)

  ASSERT_EQ(a.toi.status, CastStatus::hit);
  // Contact needs the centre within the half-diagonal (0.0866) of the top
  // face and is certain once it is within the half-width (0.05): the box
  // falls 10/3 m over the step from 1 m.
  EXPECT_GE(a.toi.fraction, (1.0 - 0.05 * std::sqrt(3.0)) * 0.3);
  EXPECT_LE(a.toi.fraction, (1.0 - 0.05) * 0.3);
  // At the reported time the box touches the plate (within 1e-9 of the
  // plate's size), and is not inside it.
  const Box bullet{Eigen::Vector3d(0.05, 0.05, 0.05), 0.0};
  const Box plate{Eigen::Vector3d(2.0, 2.0, 0.005), 0.0};
  const PenetrationResult p = penetration(bullet, pose_at(a.box_sweep, a.toi.fraction), plate,
                                          Pose::from_translation(Eigen::Vector3d(0.0, 0.0, -0.005)));
  ASSERT_EQ(p.status, Status::ok);
  EXPECT_GE(p.distance, -1e-12);
  EXPECT_LE(p.distance, 1e-9 * 2.0);
}

}  // namespace
