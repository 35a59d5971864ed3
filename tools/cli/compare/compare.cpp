// `hedra compare`'s work: the reference, hedra's and the peers' answers, the
// verdicts and both output forms (see compare.hpp for the rules).
#include "cli/compare/compare.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <hedra/hull/mesh_io.hpp>
#include <nlohmann/json.hpp>
#include <utility>

#include "cli/command.hpp"
#include "scene/timing.hpp"

#if defined(HEDRA_COMPARE_WITH_PEERS)
#  include <isolation.hpp>
#endif

namespace hedra::tool {

const char* to_string(Verdict verdict) {
  switch (verdict) {
    case Verdict::agree:
      return "agree";
    case Verdict::disagree:
      return "disagree";
    case Verdict::partial:
      return "partial";
    case Verdict::unsupported:
      return "unsupported";
    case Verdict::failed:
      return "failed";
    case Verdict::no_reference:
      return "no_reference";
  }
  return "no_reference";
}

std::optional<bool> ReferenceAnswer::intersecting() const {
  if (!exact.ok || !(std::abs(exact.distance) > tolerance)) return std::nullopt;
  return exact.distance < 0.0;
}

double angle_between(const Eigen::Vector3d& u, const Eigen::Vector3d& v) {
  // atan2 of |u x v| and u . v: accurate for small and large angles alike,
  // and independent of the lengths.
  return std::atan2(u.cross(v).norm(), u.dot(v));
}

namespace {

std::string number(double x) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3g", x);
  return text;
}

std::string vector_text(const Eigen::Vector3d& v) {
  return "[" + shortest(v[0]) + ", " + shortest(v[1]) + ", " + shortest(v[2]) + "]";
}

[[maybe_unused]] bool finite_nonzero(const Eigen::Vector3d& v) { return v.allFinite() && v.squaredNorm() > 0.0; }

}  // namespace

namespace {

// A trace that ran out of steps certifies no contact before its early end
// only: a hit is still judged by the certified distance where it is
// reported (a false hit when farther than the target, the first contact when
// within it before early); a miss, or a touch after early, is not judged.
Judgement judge_partial_trace(const ReferenceAnswer& reference, bool hit, double fraction) {
  const ReferenceAnswer::Continuous& c = *reference.continuous;
  Judgement j;
  j.verdict = Verdict::no_reference;
  j.detail = "reference unavailable: the trace ran out of steps";
  if (!hit) return j;
  const reference::DistanceBracket d = reference::distance_at(c.a, c.ma, c.b, c.mb, fraction);
  if (!d.ok) return j;
  const std::string said = "hit at " + shortest(fraction);
  if (d.lower > c.target + reference.tolerance) {
    j.verdict = Verdict::disagree;
    j.contact = reference::ContactVerdict{false, true, false, 0.0};
    j.detail = said + ": false hit (certified distance there >= " + number(d.lower) + ")";
  } else if (fraction <= c.contact.early) {
    j.verdict = Verdict::agree;
    j.contact = reference::ContactVerdict{};
    j.detail = said + " (within the target there, and no contact before it)";
  }
  return j;
}

// A continuous answer against the first contact (compare.hpp).
Judgement judge_continuous(const ReferenceAnswer& reference, const MethodAnswer& answer) {
  Judgement j;
  const std::optional<ReferenceAnswer::Continuous>& c = reference.continuous;
  if (!c || !c->contact.ok) {
    j.verdict = Verdict::no_reference;
    j.detail = !c ? "no reference" : "reference unavailable: " + c->contact.reason;
    return j;
  }
  if (!answer.supported || !answer.ok) {
    j.verdict = answer.supported ? Verdict::failed : Verdict::unsupported;
    j.detail = answer.status;
    return j;
  }
  const double fraction = c->fraction_scale > 0.0 ? answer.fraction.value_or(1.0) / c->fraction_scale : 0.0;
  if (!c->available()) return judge_partial_trace(reference, answer.intersecting, fraction);
  const reference::ContactVerdict v =
      reference::judge_contact(c->a, c->ma, c->b, c->mb, c->contact, c->target, reference.pair_size,
                               reference.tolerance, answer.intersecting, answer.intersecting ? fraction : 1.0);
  j.contact = v;
  j.distance_error = v.error * reference.pair_size;  // along the motion
  const std::string said = std::string(answer.intersecting ? "hit at " + shortest(fraction) : "no hit");
  const std::string along = number(v.error * reference.pair_size) + " along the motion";
  if (v.tunnelled) {
    j.verdict = Verdict::disagree;
    j.detail = said + ": tunnelled (" +
               (answer.intersecting ? "later than the first contact by " + along : "missed a certain contact") +
               (v.through ? ", through" : "") + ")";
  } else if (v.false_hit) {
    j.verdict = Verdict::disagree;
    j.detail = said + ": false hit (the pair is farther than the target there)";
  } else if (v.error * reference.pair_size > reference.tolerance) {
    j.verdict = Verdict::disagree;
    j.detail = said + ": early by " + along + " > " + number(reference.tolerance);
  } else {
    j.verdict = Verdict::agree;
    j.detail = said + " (error " + along + " <= " + number(reference.tolerance) + ")";
  }
  return j;
}

}  // namespace

Judgement judge(QueryType type, const ReferenceAnswer& reference, const MethodAnswer& answer) {
  if (is_continuous(type)) return judge_continuous(reference, answer);
  Judgement j;
  if (!reference.exact.ok) {
    j.verdict = Verdict::no_reference;
    j.detail = "no reference: " + reference.exact.reason;
    return j;
  }
  if (!answer.supported) {
    j.verdict = Verdict::unsupported;
    j.detail = answer.status;
    return j;
  }
  if (!answer.ok) {
    j.verdict = Verdict::failed;
    j.detail = answer.status;
    return j;
  }
  std::string problems, checks;
  auto add = [](std::string& list, const std::string& item) { list += (list.empty() ? "" : "; ") + item; };
  const double sd = reference.exact.distance;
  // Each method at the precision it computes in: a float peer's default
  // tolerances are float's (a tolerance from the scene applies to all).
  const bool at_float = answer.single_precision && !reference.tolerance_from_scene;
  const double tolerance =
      at_float ? std::max(reference.tolerance,
                          reference.exact.error_bound + kSinglePrecisionRelativeTolerance * reference.pair_size)
               : reference.tolerance;
  const double angle_tolerance = answer.single_precision
                                     ? std::max(reference.angle_tolerance, kSinglePrecisionRelativeTolerance)
                                     : reference.angle_tolerance;

  if (const std::optional<bool> expected = reference.intersecting()) {
    const std::string said = std::string("intersecting ") + (answer.intersecting ? "true" : "false");
    if (answer.intersecting != *expected) {
      add(problems, said + " (reference " + (*expected ? "true" : "false") + ")");
    } else {
      add(checks, said);
    }
  }

  bool missing_distance = false;
  if (type != QueryType::intersect) {
    const double expected = type == QueryType::distance ? std::max(sd, 0.0) : sd;
    if (!answer.distance) {
      missing_distance = true;
    } else {
      const double error = std::abs(*answer.distance - expected);
      j.distance_error = error;
      const std::string said =
          "distance " + shortest(*answer.distance) + " (reference " + shortest(expected) + ", error " + number(error);
      if (!(error <= tolerance)) {  // NaN fails
        add(problems, said + " > " + number(tolerance) + ")");
      } else {
        add(checks, said + " <= " + number(tolerance) + ")");
      }
      // The normal is compared only where the reference says it is unique,
      // and a distance query defines it only between separated shapes.
      const bool normal_defined = type == QueryType::penetration || sd > tolerance;
      if (reference.exact.normal_unique && normal_defined) {
        if (!answer.normal) {
          add(problems, "no normal (the reference's " + vector_text(reference.exact.normal) + " is unique)");
        } else {
          const double angle = angle_between(*answer.normal, reference.exact.normal);
          j.normal_angle = angle;
          const std::string said_normal = "normal " + vector_text(*answer.normal) + " (angle " + number(angle);
          if (!(angle <= angle_tolerance)) {
            add(problems, said_normal + " > " + number(angle_tolerance) + " rad)");
          } else {
            add(checks, said_normal + " <= " + number(angle_tolerance) + " rad)");
          }
        }
      }
    }
  }

  if (!problems.empty()) {
    j.verdict = Verdict::disagree;
    j.detail = problems;
  } else if (missing_distance) {
    j.verdict = Verdict::partial;
    j.detail = "no distance (" + answer.status + ")" + (checks.empty() ? "" : "; " + checks);
  } else {
    j.verdict = Verdict::agree;
    j.detail = checks.empty() ? "touching within the tolerance: either answer is right" : checks;
  }
  return j;
}

namespace {

reference::Motion motion_of(const BodySpec& body, bool rotate) {
  reference::Motion m;
  m.p0 = body.position;
  m.p1 = body.end_position;
  m.q0 = body.orientation;
  m.q1 = rotate ? body.end_orientation : body.orientation;
  return m;
}

// The first contact of a continuous query's motion (compare.hpp).
ReferenceAnswer continuous_reference(const BuiltScene& built, std::size_t index) {
  const Scene& scene = *built.scene;
  const QuerySpec& query = scene.queries[index];
  const BodySpec& body_a = scene.bodies[query.a];
  const BodySpec& body_b = scene.bodies[query.b];
  ReferenceAnswer::Continuous c;
  c.a = *built.shapes[body_a.shape];
  c.b = *built.shapes[body_b.shape];
  double far = 0.0;
  if (query.type == QueryType::raycast) {  // a point from the origin along the ray, against the still body
    c.a = collision::Sphere{0.0, 0.0};
    c.ma.p0 = query.origin;
    c.ma.p1 = query.origin + query.max_fraction * query.direction;
    c.mb = motion_of(body_a, false);
    c.mb.p1 = c.mb.p0;
    c.fraction_scale = query.max_fraction;
    far = std::max(query.origin.cwiseAbs().maxCoeff(), c.ma.p1.cwiseAbs().maxCoeff());
  } else {
    const bool rotate = query.type == QueryType::toi;
    c.ma = motion_of(body_a, rotate);
    c.mb = motion_of(body_b, rotate);
    c.target = query.target_distance;
    far = std::max(c.ma.p1.cwiseAbs().maxCoeff(), c.mb.p1.cwiseAbs().maxCoeff());
  }
  far = std::max({far, c.ma.p0.cwiseAbs().maxCoeff(), c.mb.p0.cwiseAbs().maxCoeff()});
  ReferenceAnswer r;
  r.pair_size = std::max(reference::reach(c.a), reference::reach(c.b));
  reference::FirstContactSettings settings;
  settings.target = c.target;
  settings.size = r.pair_size;
  settings.max_steps = kContinuousReferenceSteps;
  c.contact = reference::exact_first_contact(c.a, c.ma, c.b, c.mb, settings);
  r.exact.ok = c.available();
  r.exact.reason = c.contact.ok ? "the trace ran out of steps" : c.contact.reason;
  const std::optional<Expectation>& expect = query.expect;
  r.tolerance_from_scene = expect && expect->tolerance && c.contact.rate > 0.0;
  r.tolerance = r.tolerance_from_scene ? *expect->tolerance * c.contact.rate / std::max(c.fraction_scale, 1e-300)
                                       : reference::contact_tolerance(r.pair_size, far);
  r.angle_tolerance = expect && expect->angle_tolerance ? *expect->angle_tolerance : kDefaultAngleTolerance;
  r.continuous = std::move(c);
  return r;
}

}  // namespace

ReferenceAnswer reference_answer(const BuiltScene& built, std::size_t index) {
  if (is_continuous(built.scene->queries[index].type)) return continuous_reference(built, index);
  const Scene& scene = *built.scene;
  const QuerySpec& query = scene.queries[index];
  const ShapeSpec& spec_a = scene.shapes[scene.bodies[query.a].shape];
  const ShapeSpec& spec_b = scene.shapes[scene.bodies[query.b].shape];
  const collision::Shape& a = *built.shapes[scene.bodies[query.a].shape];
  const collision::Shape& b = *built.shapes[scene.bodies[query.b].shape];
  const collision::Pose& pose_a = built.poses[query.a];
  const collision::Pose& pose_b = built.poses[query.b];

  // Hulls from their input points, so that the reference does not depend
  // on hedra's quickhull either. A mesh file that cannot be read again
  // (it was read a moment ago) falls back to the built hull's vertices.
  std::vector<Eigen::Vector3d> read_a, read_b;
  auto input_points = [](const ShapeSpec& spec, std::vector<Eigen::Vector3d>& storage) {
    const std::vector<Eigen::Vector3d>* points = nullptr;
    if (spec.kind != ShapeKind::hull) return points;
    if (spec.file.empty()) return &spec.points;
    hull::ReadPointsResult read = hull::read_points(spec.resolved_file);
    if (!read.ok()) return points;
    storage = std::move(read.points);
    return static_cast<const std::vector<Eigen::Vector3d>*>(&storage);
  };
  reference::ExactSettings settings;
  settings.override_a = input_points(spec_a, read_a);
  settings.override_b = input_points(spec_b, read_b);

  ReferenceAnswer r;
  r.exact = reference::exact_signed_distance(a, pose_a, b, pose_b, settings);
  r.pair_size = pair_size(a, pose_a, b, pose_b);
  const std::optional<Expectation>& expect = query.expect;
  r.tolerance_from_scene = expect && expect->tolerance;
  r.tolerance =
      r.tolerance_from_scene ? *expect->tolerance : r.exact.error_bound + kDefaultRelativeTolerance * r.pair_size;
  r.angle_tolerance = expect && expect->angle_tolerance ? *expect->angle_tolerance : kDefaultAngleTolerance;
  return r;
}

MethodAnswer hedra_answer(const QueryOutcome& outcome) {
  MethodAnswer m;
  m.method = "hedra";
  m.description = "hedra (this build): GJK, EPA when the cores overlap";
  m.supported = true;
  m.ok = outcome.ok();
  m.status = outcome.status;
  m.intersecting = outcome.intersecting;
  m.distance = outcome.distance;
  m.normal = outcome.normal;
  m.point_a = outcome.point_a;
  m.point_b = outcome.point_b;
  m.time_ns = outcome.time_ns;
  if (is_continuous(outcome.type)) {
    m.description = "hedra (this build): raycast, shape_cast or time_of_impact";
    m.intersecting = outcome.hit || outcome.initially_overlapping;
    m.fraction = outcome.fraction;
    m.distance.reset();  // a cast's distance at the hit is not what is judged
  }
  return m;
}

namespace {

JudgedAnswer judged(QueryType type, const ReferenceAnswer& reference, MethodAnswer answer,
                    const std::optional<Eigen::Vector3d>& hedra_normal) {
  JudgedAnswer j;
  j.judgement = judge(type, reference, answer);
  if (hedra_normal && answer.normal) j.normal_angle_to_hedra = angle_between(*answer.normal, *hedra_normal);
  j.answer = std::move(answer);
  return j;
}

CompareReport compare_hedra(const LoadedScene& loaded, const CompareOptions& options) {
  CompareReport report;
  report.scene = loaded.scene.get();
  report.repeat = std::max(options.repeat, 1);
  const Scene& scene = *loaded.scene;
  for (std::size_t i = 0; i < scene.queries.size(); ++i) {
    QueryComparison q;
    q.index = i;
    q.reference = reference_answer(loaded.built, i);
    const QueryOutcome outcome = run_query(loaded.built, i, std::max(options.repeat, 1));
    q.hedra = judged(scene.queries[i].type, q.reference, hedra_answer(outcome), std::nullopt);
    report.queries.push_back(std::move(q));
  }
  return report;
}

}  // namespace

#if defined(HEDRA_COMPARE_WITH_PEERS)

namespace {

// What every peer answer says first: who answered, whether it could pose the
// question and answered, its word, its time (none for a question it could not
// pose).
template <class Method, class Result>
MethodAnswer peer_answer_header(const Method& method, const Result& result) {
  MethodAnswer m;
  m.method = method.name;
  m.description = method.description;
  m.supported = result.supported;
  m.ok = result.ok;
  m.status = result.status;
  m.time_ns = result.supported && std::isfinite(result.time_ns) ? result.time_ns : 0.0;
  m.single_precision = std::string(method.name).find("_f32") != std::string::npos;
  return m;
}

}  // namespace

MethodAnswer peer_answer(const peers::PeerMethod& method, QueryType type, const peers::PeerResult& result) {
  MethodAnswer m = peer_answer_header(method, result);
  m.intersecting = result.intersecting;
  if (!result.supported || !result.ok || !result.has_distance || type == QueryType::intersect) return m;
  if (std::isfinite(result.distance)) m.distance = result.distance;
  // A distance query defines no normal or witnesses between overlapping
  // shapes; an adapter that leaves them zero gave none.
  const bool geometry = type != QueryType::distance || !result.intersecting;
  if (geometry && finite_nonzero(result.normal)) m.normal = result.normal.normalized();
  if (geometry && result.point_a.allFinite() && result.point_b.allFinite()) {
    m.point_a = result.point_a;
    m.point_b = result.point_b;
  }
  return m;
}

MethodAnswer continuous_peer_answer(const peers::ContinuousPeerMethod& method, const peers::ToiPeerResult& result,
                                    double fraction_scale) {
  MethodAnswer m = peer_answer_header(method, result);
  if (!result.supported || !result.ok) return m;
  if (!std::isfinite(result.fraction)) {
    m.ok = false;
    m.status = "non_finite fraction";
    return m;
  }
  m.intersecting = result.hit;
  m.fraction = (result.hit ? result.fraction : 1.0) * fraction_scale;
  return m;
}

namespace {

// A peer timed as hedra is (warm_median(), timing.hpp): the last answer,
// with the median time.
template <typename Result, typename Once>
Result median_timed(const Once& once, int repeat) {
  double time_ns = 0.0;
  Result result = warm_median(repeat, time_ns, once);
  result.time_ns = time_ns;
  return result;
}

// The discrete queries `which` asked of `methods`, one run_isolated batch.
void run_discrete_peers(const LoadedScene& loaded, const CompareOptions& options,
                        const std::vector<peers::PeerMethod>& methods, const std::vector<std::size_t>& which,
                        CompareReport& report) {
  const Scene& scene = *loaded.scene;
  const BuiltScene& built = loaded.built;
  std::vector<peers::PeerPair> pairs;
  for (const std::size_t i : which) {
    const QuerySpec& query = scene.queries[i];
    pairs.push_back({*built.shapes[scene.bodies[query.a].shape], built.poses[query.a],
                     *built.shapes[scene.bodies[query.b].shape], built.poses[query.b]});
  }
  auto peer_query = [](QueryType type) {
    if (type == QueryType::intersect) return peers::PeerQuery::intersect;
    if (type == QueryType::distance) return peers::PeerQuery::distance;
    return peers::PeerQuery::penetration;
  };
  const std::size_t method_count = methods.size();
  const int repeat = std::max(options.repeat, 1);
  // One call per (query, method), run in forked children: the conversion
  // (prepare) happens there too, since a peer may crash while converting.
  auto call = [&](std::size_t k) {
    const std::size_t qi = k / method_count;
    const std::unique_ptr<peers::PreparedPair> prepared = methods[k % method_count].prepare(pairs[qi]);
    const peers::PeerQuery query = peer_query(scene.queries[which[qi]].type);
    return median_timed<peers::PeerResult>([&] { return prepared->query(query); }, repeat);
  };
  peers::IsolationSettings isolation;
  isolation.timeout_seconds = options.peer_timeout_seconds;
  const std::vector<peers::PeerResult> results = peers::run_isolated(call, which.size() * method_count, isolation);
  for (std::size_t k = 0; k < results.size(); ++k) {
    QueryComparison& q = report.queries[which[k / method_count]];
    const QueryType type = scene.queries[q.index].type;
    q.peers.push_back(
        judged(type, q.reference, peer_answer(methods[k % method_count], type, results[k]), q.hedra.answer.normal));
  }
}

// The continuous queries `which` asked of `methods` on the reference's
// motions (a ray: the point's sweep), one run_isolated batch. A cast with a
// target distance is not posed: the peers' casts have none.
void run_continuous_peers(const LoadedScene& loaded, const CompareOptions& options,
                          const std::vector<peers::ContinuousPeerMethod>& methods,
                          const std::vector<std::size_t>& which, CompareReport& report) {
  const Scene& scene = *loaded.scene;
  const std::size_t method_count = methods.size();
  const int repeat = std::max(options.repeat, 1);
  auto sweep_of = [](const reference::Motion& m) {
    return collision::Sweep{collision::Pose::from_quaternion(m.q0, m.p0), collision::Pose::from_quaternion(m.q1, m.p1)};
  };
  std::vector<peers::SweepPair> pairs;
  for (const std::size_t i : which) {
    const ReferenceAnswer::Continuous& c = *report.queries[i].reference.continuous;
    pairs.push_back({c.a, sweep_of(c.ma), c.b, sweep_of(c.mb)});
  }
  auto call = [&](std::size_t k) {
    const std::size_t qi = k / method_count;
    if (report.queries[which[qi]].reference.continuous->target > 0.0) {
      peers::ToiPeerResult r;
      r.status = "unsupported: no target distance in the peer's cast";
      return r;
    }
    const std::unique_ptr<peers::PreparedSweep> prepared = methods[k % method_count].prepare(pairs[qi]);
    return median_timed<peers::ToiPeerResult>([&] { return prepared->query(); }, repeat);
  };
  peers::IsolationSettings isolation;
  isolation.timeout_seconds = options.peer_timeout_seconds;
  const std::vector<peers::ToiPeerResult> results =
      peers::run_isolated_toi(call, which.size() * method_count, isolation);
  for (std::size_t k = 0; k < results.size(); ++k) {
    QueryComparison& q = report.queries[which[k / method_count]];
    const MethodAnswer answer =
        continuous_peer_answer(methods[k % method_count], results[k], q.reference.continuous->fraction_scale);
    q.peers.push_back(judged(scene.queries[q.index].type, q.reference, answer, std::nullopt));
  }
}

}  // namespace

CompareReport compare_scene(const LoadedScene& loaded, const CompareOptions& options,
                            const std::vector<peers::PeerMethod>& methods,
                            const std::vector<peers::ContinuousPeerMethod>& continuous_methods) {
  CompareReport report = compare_hedra(loaded, options);
  report.peers_built = true;
  report.peers_run = options.with_peers && (!methods.empty() || !continuous_methods.empty());
  if (!report.peers_run) return report;
  std::vector<std::size_t> discrete, continuous;
  for (std::size_t i = 0; i < loaded.scene->queries.size(); ++i)
    (is_continuous(loaded.scene->queries[i].type) ? continuous : discrete).push_back(i);
  if (!discrete.empty() && !methods.empty()) run_discrete_peers(loaded, options, methods, discrete, report);
  if (!continuous.empty() && !continuous_methods.empty())
    run_continuous_peers(loaded, options, continuous_methods, continuous, report);
  return report;
}

CompareReport compare_scene(const LoadedScene& loaded, const CompareOptions& options,
                            const std::vector<peers::PeerMethod>& methods) {
  return compare_scene(loaded, options, methods, peers::continuous_peer_methods());
}

CompareReport compare_scene(const LoadedScene& loaded, const CompareOptions& options) {
  return compare_scene(loaded, options, peers::peer_methods());
}

#else

CompareReport compare_scene(const LoadedScene& loaded, const CompareOptions& options) {
  CompareReport report = compare_hedra(loaded, options);
  report.peers_built = false;
  report.peers_run = false;
  return report;
}

#endif

namespace {

// hedra fails a query when it does not agree, except where a continuous
// reference was unavailable (not judged).
bool hedra_fails(const QueryComparison& q) {
  const Verdict v = q.hedra.judgement.verdict;
  return v != Verdict::agree && !(v == Verdict::no_reference && q.reference.continuous);
}

}  // namespace

int compare_exit_code(const CompareReport& report) {
  for (const QueryComparison& q : report.queries)
    if (hedra_fails(q)) return kExitCheckFailed;
  return kExitOk;
}

// ---- output ----------------------------------------------------------------

namespace {

constexpr Verdict kVerdicts[] = {Verdict::agree,       Verdict::disagree, Verdict::partial,
                                 Verdict::unsupported, Verdict::failed,   Verdict::no_reference};

const char* kPeersNotBuilt =
    "peers not built (configure with -DHEDRA_WITH_PEERS=ON): hedra is compared with the exact reference only";

struct Tally {
  std::string method;
  int counts[std::size(kVerdicts)] = {};
};

// Per method (hedra first, then the peers in order), how many of each verdict.
std::vector<Tally> tally(const CompareReport& report) {
  std::vector<Tally> tallies;
  auto count = [&](const JudgedAnswer& j) {
    auto it = std::find_if(tallies.begin(), tallies.end(), [&](const Tally& t) { return t.method == j.answer.method; });
    if (it == tallies.end()) {
      tallies.push_back({j.answer.method, {}});
      it = tallies.end() - 1;
    }
    it->counts[static_cast<int>(j.judgement.verdict)] += 1;
  };
  for (const QueryComparison& q : report.queries) {
    count(q.hedra);
    for (const JudgedAnswer& p : q.peers) count(p);
  }
  return tallies;
}

// The methods that answered (agree, disagree) split by verdict, when both
// groups are non-empty: the reference says who is right.
bool split(const QueryComparison& q, std::string& right, std::string& wrong) {
  auto add = [](std::string& list, const std::string& name) { list += (list.empty() ? "" : ", ") + name; };
  auto place = [&](const JudgedAnswer& j) {
    if (j.judgement.verdict == Verdict::agree) add(right, j.answer.method);
    if (j.judgement.verdict == Verdict::disagree) add(wrong, j.answer.method);
  };
  place(q.hedra);
  for (const JudgedAnswer& p : q.peers) place(p);
  return !right.empty() && !wrong.empty();
}

std::string short_vector(const std::optional<Eigen::Vector3d>& v) {
  if (!v) return "-";
  char text[96];
  std::snprintf(text, sizeof text, "[%.6g, %.6g, %.6g]", (*v)[0], (*v)[1], (*v)[2]);
  return text;
}

std::string optional_number(const std::optional<double>& x) { return x ? number(*x) : "-"; }

void text_row(std::string& text, const JudgedAnswer& j, bool peer) {
  const MethodAnswer& a = j.answer;
  const std::string distance = a.fraction ? shortest(*a.fraction) : a.distance ? shortest(*a.distance) : "-";
  char line[512];
  std::snprintf(line, sizeof line, "  %-21s %-12s %-5s %-22s %-9s %-9s %-9s %-32s %-32s %9s\n", a.method.c_str(),
                to_string(j.judgement.verdict), a.supported && a.ok ? (a.intersecting ? "yes" : "no") : "-",
                distance.c_str(), optional_number(j.judgement.distance_error).c_str(),
                optional_number(j.judgement.normal_angle).c_str(),
                peer ? optional_number(j.normal_angle_to_hedra).c_str() : "", short_vector(a.point_a).c_str(),
                short_vector(a.point_b).c_str(), (a.time_ns > 0.0 ? format_time(a.time_ns) : std::string("-")).c_str());
  text += line;
}

// The first contact in words, in the query's fraction units.
std::string continuous_reference_text(const ReferenceAnswer& r) {
  const ReferenceAnswer::Continuous& c = *r.continuous;
  const reference::FirstContact& f = c.contact;
  if (!f.ok) return "unavailable: " + f.reason + ": not judged\n";
  if (f.exhausted)
    return "unavailable: the trace ran out of steps (" + std::to_string(f.steps) + " steps, no contact before " +
           shortest(f.early * c.fraction_scale) + "): misses not judged, hits by the distance where reported\n";
  std::string text = "first contact ";
  if (f.initially) {
    text += "at 0 (within the target at the start)";
  } else if (!f.contact) {
    text += "none (separated all the way, smallest gap " + number(f.min_gap) + ")";
  } else if (std::isfinite(f.late)) {
    text += "in [" + shortest(f.early * c.fraction_scale) + ", " + shortest(f.late * c.fraction_scale) + "]";
  } else {
    text += "a touch at most, from " + shortest(f.early * c.fraction_scale);
  }
  return text + " (" + std::to_string(f.steps) + " steps, rate " + number(f.rate) + ", size " + number(r.pair_size) +
         ", tolerance " + number(r.tolerance) + " along the motion" +
         (r.tolerance_from_scene ? " from the scene" : "") + ")\n";
}

}  // namespace

std::string format_compare_text(const CompareReport& report) {
  const Scene& scene = *report.scene;
  std::string text = "scene " + scene.name + " (" + scene.file + "): " + std::to_string(scene.queries.size()) +
                     (scene.queries.size() == 1 ? " query" : " queries") + "; " + timing_note(report.repeat) +
                     ", every method alike\n";
  if (!report.peers_built) {
    text += std::string(kPeersNotBuilt) + "\n";
  } else if (!report.peers_run) {
    text += "peers not run: hedra is compared with the exact reference only\n";
  }
  text +=
      "verdicts against the exact reference (tools/reference): agree, disagree, partial (boolean only), "
      "unsupported, failed (error, crash or timeout)\n"
      "precision: each method is judged at the precision it computes in: double (hedra, libccd, FCL, "
      "bullet_f64_*) at the tolerance shown, float (bullet_f32_*) at that or 16 float eps x size (1.9e-6 x size, "
      "normals 1.9e-6 rad), whichever is larger\n";
  for (const QueryComparison& q : report.queries) {
    const QuerySpec& spec = scene.queries[q.index];
    const reference::ExactResult& e = q.reference.exact;
    // A ray is ray-<body>, as in `query` and `check`.
    const std::string pair = spec.type == QueryType::raycast
                                 ? "ray-" + scene.bodies[spec.a].name
                                 : scene.bodies[spec.a].name + "-" + scene.bodies[spec.b].name;
    text += "\n[" + std::to_string(q.index) + "] " + pair + " " + to_string(spec.type) + ": reference ";
    const bool continuous = q.reference.continuous.has_value();
    if (continuous) {
      text += continuous_reference_text(q.reference);
    } else if (e.ok) {
      const std::optional<bool> hit = q.reference.intersecting();
      text += "distance " + shortest(e.distance) + " (error bound " + number(e.error_bound) + ", tolerance " +
              number(q.reference.tolerance) + (q.reference.tolerance_from_scene ? " from the scene" : "") +
              "), normal " + vector_text(e.normal) + (e.normal_unique ? " (unique)" : " (not unique: not compared)") +
              ", intersecting " + (hit ? (*hit ? "true" : "false") : "either (touching within the tolerance)") + "\n";
    } else {
      text += "failed: " + e.reason + "\n";
    }
    char header[512];
    std::snprintf(header, sizeof header, "  %-21s %-12s %-5s %-22s %-9s %-9s %-9s %-32s %-32s %9s\n", "method",
                  "verdict", "hit", continuous ? "fraction" : "distance", "error", "angle", "to hedra", "point_a",
                  "point_b", "time");
    text += header;
    text_row(text, q.hedra, false);
    for (const JudgedAnswer& p : q.peers) text_row(text, p, true);
    auto explain = [&](const JudgedAnswer& j) {
      const Verdict v = j.judgement.verdict;
      if (v == Verdict::agree || (v == Verdict::no_reference && continuous)) return;  // said on the reference line
      text += "    " + j.answer.method + " " + to_string(v) + ": " + j.judgement.detail + "\n";
    };
    explain(q.hedra);
    for (const JudgedAnswer& p : q.peers) explain(p);
    std::string right, wrong;
    if (split(q, right, wrong)) text += "    methods disagree; the reference sides with: " + right + "\n";
  }

  text += "\nverdicts per method (agree / disagree / partial / unsupported / failed / no_reference):\n";
  for (const Tally& t : tally(report)) {
    char line[160];
    std::snprintf(line, sizeof line, "  %-21s %3d / %3d / %3d / %3d / %3d / %3d\n", t.method.c_str(), t.counts[0],
                  t.counts[1], t.counts[2], t.counts[3], t.counts[4], t.counts[5]);
    text += line;
  }
  std::string failing;
  for (const QueryComparison& q : report.queries)
    if (hedra_fails(q)) failing += (failing.empty() ? "" : " ") + std::to_string(q.index);
  const std::size_t n = report.queries.size();
  std::size_t not_judged = 0;
  for (const QueryComparison& q : report.queries) not_judged += q.hedra.judgement.verdict == Verdict::no_reference;
  if (failing.empty() && not_judged > 0) {
    text += "hedra agrees with the exact reference on " + std::to_string(n - not_judged) + " of " + std::to_string(n) +
            (n == 1 ? " query" : " queries") + "; " + std::to_string(not_judged) +
            " not judged (the continuous reference unavailable)\n";
  } else if (failing.empty()) {
    text += "hedra agrees with the exact reference on all " + std::to_string(n) + (n == 1 ? " query\n" : " queries\n");
  } else {
    text += "hedra does NOT agree with the exact reference on queries " + failing + " (of " + std::to_string(n) + ")\n";
  }
  return text;
}

namespace {

using Json = nlohmann::ordered_json;

Json json_vector(const std::optional<Eigen::Vector3d>& v) {
  if (!v || !v->allFinite()) return nullptr;
  return {(*v)[0], (*v)[1], (*v)[2]};
}

Json json_number(const std::optional<double>& x) {
  if (!x || !std::isfinite(*x)) return nullptr;
  return *x;
}

Json json_answer(const JudgedAnswer& j, bool peer) {
  const MethodAnswer& a = j.answer;
  Json r;
  r["method"] = a.method;
  r["precision"] = a.single_precision ? "float" : "double";
  r["description"] = a.description;
  r["supported"] = a.supported;
  r["ok"] = a.ok;
  r["status"] = a.status;
  r["intersecting"] = a.supported && a.ok ? Json(a.intersecting) : Json(nullptr);
  r["distance"] = json_number(a.distance);
  r["normal"] = json_vector(a.normal);
  r["point_a"] = json_vector(a.point_a);
  r["point_b"] = json_vector(a.point_b);
  r["time_ns"] = a.time_ns > 0.0 && std::isfinite(a.time_ns) ? Json(static_cast<long long>(std::llround(a.time_ns)))
                                                             : Json(nullptr);
  if (peer) r["normal_angle_to_hedra"] = json_number(j.normal_angle_to_hedra);
  r["verdict"] = to_string(j.judgement.verdict);
  r["detail"] = j.judgement.detail;
  r["distance_error"] = json_number(j.judgement.distance_error);
  r["normal_angle"] = json_number(j.judgement.normal_angle);
  if (a.fraction || j.judgement.contact) {  // continuous queries
    r["hit"] = a.supported && a.ok ? Json(a.intersecting) : Json(nullptr);
    r["fraction"] = json_number(a.fraction);
    const std::optional<reference::ContactVerdict>& v = j.judgement.contact;
    r["tunnelled"] = v ? Json(v->tunnelled) : Json(nullptr);
    r["through"] = v ? Json(v->through) : Json(nullptr);
    r["false_hit"] = v ? Json(v->false_hit) : Json(nullptr);
    r["fraction_error"] = v ? json_number(v->error) : Json(nullptr);  // along the motion / size
  }
  return r;
}

}  // namespace

std::string format_compare_json(const CompareReport& report) {
  const Scene& scene = *report.scene;
  Json document;
  document["scene"] = scene.name;
  document["file"] = scene.file;
  document["peers_built"] = report.peers_built;
  document["peers_run"] = report.peers_run;
  document["timing"] = timing_note(report.repeat) + ", every method alike";
  document["timed_calls"] = report.repeat;
  if (!report.peers_built) document["note"] = kPeersNotBuilt;
  Json queries = Json::array();
  for (const QueryComparison& q : report.queries) {
    const QuerySpec& spec = scene.queries[q.index];
    const reference::ExactResult& e = q.reference.exact;
    Json r;
    r["index"] = q.index;
    r["a"] = scene.bodies[spec.a].name;
    r["b"] = scene.bodies[spec.b].name;
    r["type"] = to_string(spec.type);
    Json ref;
    ref["ok"] = e.ok;
    if (const std::optional<ReferenceAnswer::Continuous>& c = q.reference.continuous) {
      const reference::FirstContact& f = c->contact;
      Json first;
      first["available"] = c->available();
      first["reason"] = c->available() ? Json(nullptr) : Json(e.reason);
      first["initially"] = f.initially;
      first["contact"] = f.contact;
      first["early"] = f.contact ? json_number(f.early * c->fraction_scale) : Json(nullptr);
      first["late"] = f.contact ? json_number(f.late * c->fraction_scale) : Json(nullptr);  // null: a touch at most
      first["min_gap"] = json_number(f.min_gap);
      first["rate"] = json_number(f.rate);
      first["steps"] = f.steps;
      first["max_steps"] = kContinuousReferenceSteps;
      first["target"] = c->target;
      ref["first_contact"] = std::move(first);
    } else if (!e.ok) {
      ref["reason"] = e.reason;
    } else {
      const std::optional<bool> hit = q.reference.intersecting();
      ref["distance"] = json_number(e.distance);
      ref["error_bound"] = json_number(e.error_bound);
      ref["lower"] = json_number(e.lower);
      ref["upper"] = json_number(e.upper);
      ref["intersecting"] = hit ? Json(*hit) : Json(nullptr);
      ref["normal"] = json_vector(e.normal);
      ref["normal_unique"] = e.normal_unique;
      ref["point_a"] = json_vector(e.point_a);
      ref["point_b"] = json_vector(e.point_b);
      ref["curved"] = e.curved;
    }
    ref["pair_size"] = json_number(q.reference.pair_size);
    ref["tolerance"] = json_number(q.reference.tolerance);
    ref["tolerance_from_scene"] = q.reference.tolerance_from_scene;
    ref["angle_tolerance"] = json_number(q.reference.angle_tolerance);
    r["reference"] = std::move(ref);
    r["hedra"] = json_answer(q.hedra, false);
    Json peer_list = Json::array();
    for (const JudgedAnswer& p : q.peers) peer_list.push_back(json_answer(p, true));
    r["peers"] = std::move(peer_list);
    std::string right, wrong;
    r["methods_split"] = split(q, right, wrong);
    queries.push_back(std::move(r));
  }
  document["queries"] = std::move(queries);
  Json summary;
  summary["queries"] = report.queries.size();
  summary["hedra_agrees"] = compare_exit_code(report) == kExitOk;
  int not_judged = 0;
  for (const QueryComparison& q : report.queries) not_judged += q.hedra.judgement.verdict == Verdict::no_reference;
  summary["hedra_not_judged"] = not_judged;
  Json verdicts;
  for (const Tally& t : tally(report)) {
    Json counts;
    for (std::size_t v = 0; v < std::size(kVerdicts); ++v) counts[to_string(kVerdicts[v])] = t.counts[v];
    verdicts[t.method] = std::move(counts);
  }
  summary["verdicts"] = std::move(verdicts);
  document["summary"] = std::move(summary);
  return document.dump() + "\n";
}

}  // namespace hedra::tool
