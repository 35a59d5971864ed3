// Query execution for the scene commands (see scene_runner.hpp).
#include "scene/scene_runner.hpp"

#include <charconv>
#include <cmath>
#include <hedra/collision/cast.hpp>
#include <hedra/collision/manifold.hpp>
#include <hedra/collision/query.hpp>
#include <hedra/collision/raycast.hpp>
#include <hedra/collision/time_of_impact.hpp>
#include <hedra/collision/world.hpp>
#include <hedra/hull/assert.hpp>
#include <optional>
#include <utility>

#include "scene/timing.hpp"

namespace hedra::tool {

namespace {

// Every query is timed the same way: warm_median() (timing.hpp).
template <class Call>
auto timed(int repeat, double& time_ns, Call&& call) {
  return warm_median(repeat, time_ns, std::forward<Call>(call));
}

bool finite(const Eigen::Vector3d& v) { return v.allFinite(); }

// Zero without its sign: a touching pair's signed distance is -(0 depth) =
// -0, which readers of the output would take for a (tiny) penetration.
double unsigned_zero(double x) { return x == 0.0 ? 0.0 : x; }
Eigen::Vector3d unsigned_zero(const Eigen::Vector3d& v) {
  return {unsigned_zero(v.x()), unsigned_zero(v.y()), unsigned_zero(v.z())};
}

// Fills the geometric outputs, keeping only finite ones: a non-finite value
// is dropped and reported as status "non_finite" (never printed as NaN).
void set_geometry(QueryOutcome& out, double distance, const Eigen::Vector3d& normal, const Eigen::Vector3d& point_a,
                  const Eigen::Vector3d& point_b, bool with_normal) {
  if (std::isfinite(distance)) {
    out.distance = unsigned_zero(distance);
  } else if (out.ok()) {
    out.status = "non_finite";
  }
  if (!with_normal) return;
  if (finite(normal) && finite(point_a) && finite(point_b) && normal.squaredNorm() > 0.0) {
    out.normal = unsigned_zero(normal);
    out.point_a = unsigned_zero(point_a);
    out.point_b = unsigned_zero(point_b);
  } else if (out.ok()) {
    out.status = "non_finite";
  }
}

QueryOutcome run_intersect(const collision::Shape& a, const collision::Pose& pa, const collision::Shape& b,
                           const collision::Pose& pb, int repeat) {
  QueryOutcome out;
  out.type = QueryType::intersect;
  const collision::IntersectResult r = timed(repeat, out.time_ns, [&] { return collision::intersect(a, pa, b, pb); });
  out.status = collision::to_string(r.status);
  out.intersecting = r.intersecting;
  out.gjk_iterations = r.iterations;
  out.support_calls = r.support_calls;
  return out;
}

QueryOutcome run_distance(const collision::Shape& a, const collision::Pose& pa, const collision::Shape& b,
                          const collision::Pose& pb, int repeat) {
  QueryOutcome out;
  out.type = QueryType::distance;
  const collision::DistanceResult r = timed(repeat, out.time_ns, [&] { return collision::distance(a, pa, b, pb); });
  out.status = collision::to_string(r.status);
  out.intersecting = r.intersecting;
  out.gjk_iterations = r.iterations;
  out.support_calls = r.support_calls;
  out.error_bound = std::isfinite(r.error_bound) ? r.error_bound : 0.0;
  // The normal and closest points are defined only between separated
  // shapes (DistanceResult: valid when ok and not intersecting).
  const bool separated = r.status == collision::Status::ok && !r.intersecting;
  set_geometry(out, r.distance, r.normal, r.point_a, r.point_b, separated);
  return out;
}

// A penetration() answer as the query's outcome (the penetration query's,
// and a contact query's whose manifold found the pair apart).
void set_penetration(QueryOutcome& out, const collision::PenetrationResult& r) {
  out.status = collision::to_string(r.status);
  out.intersecting = r.intersecting;
  out.gjk_iterations = r.gjk_iterations;
  out.epa_iterations = r.epa_iterations;
  out.support_calls = r.support_calls;
  // PenetrationResult reports EPA only through its iteration count, so this
  // reads "EPA expanded": an EPA entered on touching cores that answers from
  // a flat GJK simplex without one expansion shows as not run.
  out.epa_ran = r.epa_iterations > 0;
  out.error_bound = std::isfinite(r.error_bound) ? r.error_bound : 0.0;
  // Outputs are finite (best so far) for every status but these two.
  if (r.status != collision::Status::degenerate && r.status != collision::Status::invalid_input)
    set_geometry(out, r.distance, r.normal, r.point_a, r.point_b, true);
}

QueryOutcome run_penetration(const collision::Shape& a, const collision::Pose& pa, const collision::Shape& b,
                             const collision::Pose& pb, int repeat) {
  QueryOutcome out;
  out.type = QueryType::penetration;
  const collision::PenetrationResult r =
      timed(repeat, out.time_ns, [&] { return collision::penetration(a, pa, b, pb); });
  set_penetration(out, r);
  return out;
}

// The contact query: collision::contact() (SAT + clipping for polytopes,
// dedicated paths for curved shapes, see manifold.hpp), its deepest
// witnesses as point_a/point_b and its manifold as `contacts`. The format
// answers a contact query "as penetration": when the manifold finds the pair
// separated beyond its contact distance (the query's `contact_distance`,
// default 0; a SAT lower bound, no witnesses),
// the exact distance and closest points come from collision::penetration(),
// timed together with the manifold.
QueryOutcome run_contact(const collision::Shape& a, const collision::Pose& pa, const collision::Shape& b,
                         const collision::Pose& pb, const QuerySpec& query, int repeat) {
  collision::ContactSettings settings;
  settings.contact_distance = query.contact_distance;
  QueryOutcome out;
  out.type = QueryType::contact;
  struct Answer {
    collision::ContactResult manifold;
    std::optional<collision::PenetrationResult> exact;
  };
  const Answer r = timed(repeat, out.time_ns, [&] {
    Answer answer{collision::contact(a, pa, b, pb, nullptr, settings), std::nullopt};
    if (answer.manifold.path == collision::ContactPath::separated && answer.manifold.count == 0) {
      answer.exact = collision::penetration(a, pa, b, pb);
    }
    return answer;
  });
  out.manifold_ran = true;
  if (r.exact) {
    set_penetration(out, *r.exact);
    return out;
  }
  const collision::ContactResult& m = r.manifold;
  out.status = collision::to_string(m.status);
  out.intersecting = m.intersecting;
  out.error_bound = std::isfinite(m.error_bound) ? m.error_bound : 0.0;
  const bool defined = m.status != collision::Status::degenerate && m.status != collision::Status::invalid_input;
  if (defined) {
    set_geometry(out, m.distance, m.normal, m.point_a, m.point_b, true);
    for (int i = 0; i < m.count; ++i) {
      const collision::ContactPoint& c = m.points[static_cast<std::size_t>(i)];
      if (!finite(c.point) || !std::isfinite(c.depth)) {
        if (out.ok()) out.status = "non_finite";
        continue;
      }
      out.contacts.push_back({unsigned_zero(c.point), unsigned_zero(c.depth)});
    }
  }
  return out;
}

// ---- continuous queries ------------------------------------------------------

// "ok" for the three verdicts, the library's word otherwise.
std::string cast_status(collision::CastStatus status) {
  switch (status) {
    case collision::CastStatus::hit:
    case collision::CastStatus::separated:
    case collision::CastStatus::initially_overlapping:
      return "ok";
    default:
      return collision::to_string(status);
  }
}

// A vector output: finite, or zero with status "non_finite".
Eigen::Vector3d finite_or_zero(QueryOutcome& out, const Eigen::Vector3d& v) {
  if (finite(v)) return unsigned_zero(v);
  if (out.ok()) out.status = "non_finite";
  return Eigen::Vector3d::Zero();
}
double finite_or_zero(QueryOutcome& out, double x) {
  if (std::isfinite(x)) return unsigned_zero(x);
  if (out.ok()) out.status = "non_finite";
  return 0.0;
}

QueryOutcome run_raycast(const collision::Shape& shape, const collision::Pose& pose, const QuerySpec& query,
                         int repeat) {
  QueryOutcome out;
  out.type = QueryType::raycast;
  const collision::RaycastResult r = timed(repeat, out.time_ns, [&] {
    return collision::raycast(shape, pose, query.origin, query.direction, query.max_fraction);
  });
  out.status = cast_status(r.status);
  out.hit = r.hit;
  out.intersecting = r.hit;
  out.initially_overlapping = r.started_inside;
  out.fraction = finite_or_zero(out, r.fraction);
  out.point = finite_or_zero(out, r.point);
  out.normal = finite_or_zero(out, r.normal);
  out.cast_iterations = r.iterations;
  out.error_bound = std::isfinite(r.error_bound) ? r.error_bound : 0.0;
  return out;
}

// A hit's distance is documented in [target, target + tolerance]; the
// rounding of its witness points can put it a few ulps below the target
// (-2e-16 for a touching target of 0), which the output shows at the
// target itself.
void set_cast(QueryOutcome& out, const collision::CastResult& r, double target) {
  out.status = cast_status(r.status);
  out.hit = r.hit;
  out.intersecting = r.hit;
  out.initially_overlapping = r.initially_overlapping;
  out.fraction = finite_or_zero(out, r.fraction);
  out.distance = finite_or_zero(out, r.distance);
  if (r.status == collision::CastStatus::hit && out.distance && *out.distance < target) out.distance = target;
  out.normal = finite_or_zero(out, r.normal);
  out.point_a = finite_or_zero(out, r.point_a);
  out.point_b = finite_or_zero(out, r.point_b);
  out.cast_iterations = r.iterations;
  out.support_calls = r.support_calls;
  out.error_bound = std::isfinite(r.error_bound) ? r.error_bound : 0.0;
}

// Translation only: each body from its position to its end position, at its
// start orientation.
QueryOutcome run_cast(const collision::Shape& a, const BodySpec& body_a, const collision::Shape& b,
                      const BodySpec& body_b, const QuerySpec& query, int repeat) {
  QueryOutcome out;
  out.type = QueryType::cast;
  collision::ShapeCastSettings settings;
  settings.target_distance = query.target_distance;
  const collision::Pose pa = body_a.pose();
  const collision::Pose pb = body_b.pose();
  const Eigen::Vector3d ua = body_a.end_position - body_a.position;
  const Eigen::Vector3d ub = body_b.end_position - body_b.position;
  set_cast(out,
           timed(repeat, out.time_ns, [&] { return collision::shape_cast(a, pa, ua, b, pb, ub, nullptr, settings); }),
           settings.target_distance + settings.linear_slop);
  return out;
}

QueryOutcome run_toi(const collision::Shape& a, const BodySpec& body_a, const collision::Shape& b,
                     const BodySpec& body_b, const QuerySpec& query, int repeat) {
  QueryOutcome out;
  out.type = QueryType::toi;
  collision::ToiSettings settings;
  settings.target_distance = query.target_distance;
  const collision::Sweep sa{body_a.pose(), body_a.end_pose()};
  const collision::Sweep sb{body_b.pose(), body_b.end_pose()};
  set_cast(out, timed(repeat, out.time_ns, [&] { return collision::time_of_impact(a, sa, b, sb, nullptr, settings); }),
           settings.target_distance + settings.linear_slop);
  return out;
}

}  // namespace

namespace {

// One answered pair of World::pairs as an outcome (the fields its single
// query would fill, iteration counts aside).
QueryOutcome pair_outcome(const collision::PairResult& r, QueryType type) {
  QueryOutcome out;
  out.type = type;
  out.body_a = r.a;
  out.body_b = r.b;
  out.status = collision::to_string(r.status);
  out.intersecting = r.intersecting;
  out.error_bound = std::isfinite(r.error_bound) ? r.error_bound : 0.0;
  const bool defined = r.status != collision::Status::degenerate && r.status != collision::Status::invalid_input;
  switch (type) {
    case QueryType::intersect:
      break;
    case QueryType::distance:
      set_geometry(out, r.distance, r.normal, r.point_a, r.point_b,
                   r.status == collision::Status::ok && !r.intersecting);
      break;
    case QueryType::contact:
      out.manifold_ran = true;
      for (int i = 0; defined && i < r.count; ++i) {
        const collision::ContactPoint& c = r.points[static_cast<std::size_t>(i)];
        if (!finite(c.point) || !std::isfinite(c.depth)) {
          if (out.ok()) out.status = "non_finite";
          continue;
        }
        out.contacts.push_back({unsigned_zero(c.point), unsigned_zero(c.depth)});
      }
      [[fallthrough]];
    default:
      if (defined) set_geometry(out, r.distance, r.normal, r.point_a, r.point_b, true);
      break;
  }
  return out;
}

collision::PairQuery pair_query(QueryType type) {
  switch (type) {
    case QueryType::intersect:
      return collision::PairQuery::intersect;
    case QueryType::distance:
      return collision::PairQuery::distance;
    case QueryType::contact:
      return collision::PairQuery::contact;
    default:
      return collision::PairQuery::penetration;
  }
}

QueryOutcome run_single(const BuiltScene& built, const QuerySpec& query, const collision::Shape& a,
                        const collision::Pose& pa, const collision::Shape& b, const collision::Pose& pb, int repeat);

}  // namespace

AllPairsOutcome run_all_pairs(const BuiltScene& built, std::size_t index, int repeat, int threads) {
  const Scene& scene = *built.scene;
  const QuerySpec& query = scene.queries[index];
  collision::PairSettings settings;
  settings.query = pair_query(query.type);
  settings.max_distance = query.max_distance;
  settings.parallel.threads = threads;
  AllPairsOutcome result;
  result.bodies = scene.bodies.size();
  struct Answer {
    std::vector<collision::PairResult> pairs;
    std::size_t candidates = 0;
  };
  // Each call starts from a new World: adding the bodies and building the
  // tree are part of the query's time.
  const Answer answer = timed(repeat, result.time_ns, [&] {
    Answer a;
    collision::World world;
    for (std::size_t i = 0; i < scene.bodies.size(); ++i) {
      // build_shapes() built every body's shape for an all-pairs query, and
      // the reader validated every pose.
      const std::uint32_t body = world.add(*built.shapes[scene.bodies[i].shape], built.poses[i]);
      (void)body;
      HEDRA_ASSERT(body == i);
    }
    world.pairs(settings, a.pairs);
    a.candidates = world.stats().candidates;
    return a;
  });
  result.candidates = answer.candidates;
  const std::vector<collision::PairResult>& pairs = answer.pairs;
  result.pairs.reserve(pairs.size());
  for (const collision::PairResult& r : pairs) {
    result.pairs.push_back(pair_outcome(r, query.type));
    result.pairs.back().time_ns = result.time_ns;
  }
  return result;
}

void expand_all_pairs(Scene& scene, BuiltScene& built, int threads) {
  HEDRA_ASSERT(built.scene == &scene);
  std::vector<QuerySpec> queries;
  for (std::size_t i = 0; i < scene.queries.size(); ++i) {
    const QuerySpec& query = scene.queries[i];
    if (!query.all_pairs) {
      queries.push_back(query);
      continue;
    }
    for (const QueryOutcome& pair : run_all_pairs(built, i, 1, threads).pairs) {
      QuerySpec single;
      single.type = query.type;
      single.a = pair.body_a;
      single.b = pair.body_b;
      single.contact_distance = query.max_distance;
      queries.push_back(single);
    }
  }
  scene.queries = std::move(queries);
}

QueryOutcome run_query(const BuiltScene& built, std::size_t index, int repeat) {
  const Scene& scene = *built.scene;
  const QuerySpec& query = scene.queries[index];
  HEDRA_ASSERT(!query.all_pairs);  // run_all_pairs answers those
  const std::size_t shape_a = scene.bodies[query.a].shape;
  const std::size_t shape_b = scene.bodies[query.b].shape;
  // build_shapes() built every shape a query uses.
  const collision::Shape& a = *built.shapes[shape_a];
  const collision::Shape& b = *built.shapes[shape_b];
  const collision::Pose& pa = built.poses[query.a];
  const collision::Pose& pb = built.poses[query.b];
  QueryOutcome out = run_single(built, query, a, pa, b, pb, repeat);
  out.body_a = query.a;
  out.body_b = query.b;
  return out;
}

namespace {

QueryOutcome run_single(const BuiltScene& built, const QuerySpec& query, const collision::Shape& a,
                        const collision::Pose& pa, const collision::Shape& b, const collision::Pose& pb, int repeat) {
  const Scene& scene = *built.scene;
  switch (query.type) {
    case QueryType::intersect:
      return run_intersect(a, pa, b, pb, repeat);
    case QueryType::distance:
      return run_distance(a, pa, b, pb, repeat);
    case QueryType::penetration:
      return run_penetration(a, pa, b, pb, repeat);
    case QueryType::contact:
      return run_contact(a, pa, b, pb, query, repeat);
    case QueryType::raycast:
      return run_raycast(a, pa, query, repeat);
    case QueryType::cast:
      return run_cast(a, scene.bodies[query.a], b, scene.bodies[query.b], query, repeat);
    case QueryType::toi:
      return run_toi(a, scene.bodies[query.a], b, scene.bodies[query.b], query, repeat);
  }
  return run_contact(a, pa, b, pb, query, repeat);
}

}  // namespace

std::optional<LoadedScene> prepare_scene(const std::string& path, std::string& error) {
  LoadSceneResult loaded = load_scene(path);
  if (!loaded.ok()) {
    error = loaded.error;
    return std::nullopt;
  }
  LoadedScene result;
  result.scene = std::make_unique<Scene>(std::move(*loaded.scene));
  BuildShapesResult built = build_shapes(*result.scene);
  if (!built.ok()) {
    error = built.error;
    return std::nullopt;
  }
  result.built = std::move(*built.built);
  return result;
}

std::string shortest(double x) {
  char text[64];
  const std::to_chars_result r = std::to_chars(text, text + sizeof text, x);
  return std::string(text, r.ptr);
}

}  // namespace hedra::tool
