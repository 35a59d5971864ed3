// `hedra compare` (tools/cli/compare/): the verdict rules of judge() on
// fabricated answers (a hedra result made wrong on purpose must fail the
// exit code), compare_scene with fabricated peers that crash, hang, cannot
// pose the question or answer wrongly (each reported, none failing the
// tool), and the subcommand end to end: the reference and verdicts of
// closed-form sphere pairs, a well-formed --json document, a real
// unsupported peer (FCL has no margins), bad input exactly as `hedra query`
// reports it. Continuous queries: hedra judged against the exact first
// contact (late, missed, early and false hits failing it; a trace that runs
// out not judged), and fabricated continuous peers that crash or tunnel
// reported without failing the command.
#include "cli/compare/compare.hpp"

#include <Eigen/Core>
#include <cmath>
#include <cstdlib>
#include <string>
#include <thread>
#include <vector>

#include "cli_fixture.hpp"

namespace {

using namespace hedra::tool;
using namespace hedra::cli_test;

// ---- judge(): the rules, on fabricated answers -------------------------------

ReferenceAnswer reference_of(double distance, const Eigen::Vector3d& normal, bool normal_unique,
                             double tolerance = 1e-9) {
  ReferenceAnswer r;
  r.exact.ok = true;
  r.exact.distance = r.exact.lower = r.exact.upper = distance;
  r.exact.normal = normal;
  r.exact.normal_unique = normal_unique;
  r.pair_size = 1.0;
  r.tolerance = tolerance;
  r.angle_tolerance = 1e-6;
  return r;
}

MethodAnswer answer_of(bool intersecting, std::optional<double> distance,
                       std::optional<Eigen::Vector3d> normal = std::nullopt) {
  MethodAnswer a;
  a.method = "m";
  a.status = "ok";
  a.intersecting = intersecting;
  a.distance = distance;
  a.normal = normal;
  return a;
}

const Eigen::Vector3d kZ = Eigen::Vector3d::UnitZ();

TEST(CompareJudge, DistanceWithinTheToleranceAgreesAndBeyondItDisagrees) {
  const ReferenceAnswer r = reference_of(-0.25, kZ, true, 1e-9);
  Judgement j = judge(QueryType::penetration, r, answer_of(true, -0.25 + 0.9e-9, kZ));
  EXPECT_EQ(j.verdict, Verdict::agree) << j.detail;
  ASSERT_TRUE(j.distance_error.has_value());
  EXPECT_NEAR(*j.distance_error, 0.9e-9, 1e-15);
  j = judge(QueryType::penetration, r, answer_of(true, -0.25 + 1.1e-9, kZ));
  EXPECT_EQ(j.verdict, Verdict::disagree);
  EXPECT_NE(j.detail.find("distance"), std::string::npos) << j.detail;
  // A distance query compares with max(sd, 0): 0 is right for overlapping
  // shapes, the depth is not.
  EXPECT_EQ(judge(QueryType::distance, r, answer_of(true, 0.0)).verdict, Verdict::agree);
  EXPECT_EQ(judge(QueryType::distance, r, answer_of(true, -0.25)).verdict, Verdict::disagree);
}

// A method is judged at the precision it computes in: Bullet's float build
// rounds a distance of 0.01 to 0.00999999 (an error of 9.5e-9), which is
// float rounding, not a wrong answer; the same error from a double method
// is one.
TEST(CompareJudge, FloatPeersAreJudgedAtFloatPrecision) {
  ReferenceAnswer r = reference_of(-0.01, kZ, true, 3.37e-9);
  r.pair_size = 0.337;
  MethodAnswer in_double = answer_of(true, -0.009999990463256836, kZ);
  EXPECT_EQ(judge(QueryType::penetration, r, in_double).verdict, Verdict::disagree);
  MethodAnswer in_float = in_double;
  in_float.single_precision = true;
  const Judgement j = judge(QueryType::penetration, r, in_float);
  EXPECT_EQ(j.verdict, Verdict::agree) << j.detail;
  // Float precision is still a bound: 1e-5 off is wrong in float too.
  in_float.distance = -0.01 + 1e-5;
  EXPECT_EQ(judge(QueryType::penetration, r, in_float).verdict, Verdict::disagree);
  // A tolerance the scene states applies to every method alike.
  r.tolerance_from_scene = true;
  in_float.distance = -0.009999990463256836;
  EXPECT_EQ(judge(QueryType::penetration, r, in_float).verdict, Verdict::disagree);
}

TEST(CompareJudge, IntersectingIsComparedOnlyOutsideTheTolerance) {
  const ReferenceAnswer touching = reference_of(0.5e-9, kZ, false, 1e-9);
  EXPECT_FALSE(touching.intersecting().has_value());
  EXPECT_EQ(judge(QueryType::intersect, touching, answer_of(true, std::nullopt)).verdict, Verdict::agree);
  EXPECT_EQ(judge(QueryType::intersect, touching, answer_of(false, std::nullopt)).verdict, Verdict::agree);
  const ReferenceAnswer apart = reference_of(2e-9, kZ, true, 1e-9);
  ASSERT_TRUE(apart.intersecting().has_value());
  EXPECT_FALSE(*apart.intersecting());
  EXPECT_EQ(judge(QueryType::intersect, apart, answer_of(false, std::nullopt)).verdict, Verdict::agree);
  EXPECT_EQ(judge(QueryType::intersect, apart, answer_of(true, std::nullopt)).verdict, Verdict::disagree);
}

TEST(CompareJudge, NormalsAreComparedByAngleOnlyWhereTheReferenceSaysUnique) {
  const Eigen::Vector3d tilted(std::sin(2e-6), 0.0, std::cos(2e-6));  // 2e-6 rad from z
  const Eigen::Vector3d close(std::sin(0.5e-6), 0.0, std::cos(0.5e-6));
  const ReferenceAnswer unique = reference_of(-0.1, kZ, true);
  Judgement j = judge(QueryType::penetration, unique, answer_of(true, -0.1, tilted));
  EXPECT_EQ(j.verdict, Verdict::disagree) << j.detail;
  ASSERT_TRUE(j.normal_angle.has_value());
  EXPECT_NEAR(*j.normal_angle, 2e-6, 1e-12);
  EXPECT_EQ(judge(QueryType::penetration, unique, answer_of(true, -0.1, 3.0 * close)).verdict, Verdict::agree);
  EXPECT_EQ(judge(QueryType::penetration, unique, answer_of(true, -0.1)).verdict, Verdict::disagree)
      << "a unique normal that the method does not give";
  // Not unique (curved pairs, ties): any normal is accepted.
  const ReferenceAnswer tie = reference_of(-0.1, kZ, false);
  j = judge(QueryType::penetration, tie, answer_of(true, -0.1, Eigen::Vector3d::UnitX()));
  EXPECT_EQ(j.verdict, Verdict::agree) << j.detail;
  EXPECT_FALSE(j.normal_angle.has_value());
  // A distance query between overlapping shapes defines no normal.
  EXPECT_EQ(judge(QueryType::distance, unique, answer_of(true, 0.0)).verdict, Verdict::agree);
}

TEST(CompareJudge, PartialUnsupportedFailedAndNoReference) {
  const ReferenceAnswer r = reference_of(0.5, kZ, true);
  // The boolean only (libccd on separated pairs): partial when it agrees,
  // disagree when it does not.
  EXPECT_EQ(judge(QueryType::distance, r, answer_of(false, std::nullopt)).verdict, Verdict::partial);
  EXPECT_EQ(judge(QueryType::distance, r, answer_of(true, std::nullopt)).verdict, Verdict::disagree);
  MethodAnswer unsupported = answer_of(false, std::nullopt);
  unsupported.supported = false;
  unsupported.status = "unsupported: no margins";
  Judgement j = judge(QueryType::distance, r, unsupported);
  EXPECT_EQ(j.verdict, Verdict::unsupported);
  EXPECT_EQ(j.detail, "unsupported: no margins");
  MethodAnswer failed = answer_of(false, 0.5, kZ);
  failed.ok = false;
  failed.status = "crashed: signal 6 (Aborted)";
  EXPECT_EQ(judge(QueryType::distance, r, failed).verdict, Verdict::failed);
  ReferenceAnswer none = r;
  none.exact.ok = false;
  none.exact.reason = "qhull error";
  EXPECT_EQ(judge(QueryType::distance, none, answer_of(false, 0.5, kZ)).verdict, Verdict::no_reference);
}

// ---- exit code: a hedra result forced to disagree -------------------------

TEST(CompareExitCode, OneWhenHedraDisagreesOnAnyQueryNeverForPeers) {
  CompareReport report;
  for (int i = 0; i < 2; ++i) {
    QueryComparison q;
    q.index = static_cast<std::size_t>(i);
    q.reference = reference_of(1.0, kZ, true);
    q.hedra.answer = answer_of(false, 1.0, kZ);
    q.hedra.judgement = judge(QueryType::distance, q.reference, q.hedra.answer);
    JudgedAnswer wrong_peer;
    wrong_peer.answer = answer_of(false, 1.5, kZ);
    wrong_peer.judgement = judge(QueryType::distance, q.reference, wrong_peer.answer);
    ASSERT_EQ(wrong_peer.judgement.verdict, Verdict::disagree);
    q.peers.push_back(wrong_peer);
    report.queries.push_back(q);
  }
  EXPECT_EQ(compare_exit_code(report), 0) << "peers' disagreements are not failures";
  // hedra's second answer made wrong by 1e-6 (the tolerance is 1e-9).
  report.queries[1].hedra.answer.distance = 1.0 + 1e-6;
  report.queries[1].hedra.judgement =
      judge(QueryType::distance, report.queries[1].reference, report.queries[1].hedra.answer);
  EXPECT_EQ(report.queries[1].hedra.judgement.verdict, Verdict::disagree);
  EXPECT_EQ(compare_exit_code(report), 1);
  // A failed hedra query (status not ok) fails too.
  report.queries[1].hedra.answer.distance = 1.0;
  report.queries[1].hedra.answer.ok = false;
  report.queries[1].hedra.answer.status = "max_iterations";
  report.queries[1].hedra.judgement =
      judge(QueryType::distance, report.queries[1].reference, report.queries[1].hedra.answer);
  EXPECT_EQ(compare_exit_code(report), 1);
}

// ---- compare_scene on a scene in memory ------------------------------------

// Two unit balls 5 apart (distance 3, normal (0.6, 0.8, 0)) and two
// overlapping by 0.5 along x (signed distance -0.5, normal +x).
const char* kBallsScene = R"({"hedra_scene": 1, "name": "balls",
  "shapes": {"ball": {"type": "sphere", "radius": 1}},
  "bodies": {"p": {"shape": "ball"}, "q": {"shape": "ball", "position": [3, 4, 0]},
             "r": {"shape": "ball", "position": [1.5, 0, 0]}},
  "queries": [{"a": "p", "b": "q", "type": "distance"},
              {"a": "p", "b": "r", "type": "penetration"},
              {"a": "p", "b": "q", "type": "intersect"}]})";

// The scene parsed and built, or a test failure (and no scene).
std::optional<LoadedScene> load(const std::string& text) {
  LoadSceneResult parsed = parse_scene(text, "balls.json");
  if (!parsed.ok()) {
    ADD_FAILURE() << parsed.error;
    return std::nullopt;
  }
  LoadedScene loaded;
  loaded.scene = std::make_unique<Scene>(std::move(*parsed.scene));
  BuildShapesResult built = build_shapes(*loaded.scene);
  if (!built.ok()) {
    ADD_FAILURE() << built.error;
    return std::nullopt;
  }
  loaded.built = std::move(*built.built);
  return loaded;
}

TEST(CompareScene, ReferenceOfSpherePairsIsTheClosedForm) {
  const std::optional<LoadedScene> loaded = load(kBallsScene);
  ASSERT_TRUE(loaded);
  CompareOptions options;
  options.with_peers = false;
  const CompareReport report = compare_scene(*loaded, options);
  ASSERT_EQ(report.queries.size(), 3u);
  EXPECT_FALSE(report.peers_run);
  const ReferenceAnswer& apart = report.queries[0].reference;
  ASSERT_TRUE(apart.exact.ok) << apart.exact.reason;
  EXPECT_NEAR(apart.exact.distance, 3.0, 1e-14);
  EXPECT_TRUE(apart.exact.normal_unique);
  EXPECT_NEAR((apart.exact.normal - Eigen::Vector3d(0.6, 0.8, 0)).norm(), 0.0, 1e-14);
  // Tolerance: the reference's error bound + 1e-9 of the pair size (half of
  // 5 + radius 1 = 3.5).
  EXPECT_NEAR(apart.tolerance, apart.exact.error_bound + 3.5e-9, 1e-18);
  const ReferenceAnswer& overlap = report.queries[1].reference;
  ASSERT_TRUE(overlap.exact.ok) << overlap.exact.reason;
  EXPECT_NEAR(overlap.exact.distance, -0.5, 1e-14);
  ASSERT_TRUE(overlap.intersecting().has_value());
  EXPECT_TRUE(*overlap.intersecting());
  for (const QueryComparison& q : report.queries) {
    EXPECT_EQ(q.hedra.judgement.verdict, Verdict::agree) << q.hedra.judgement.detail;
    EXPECT_TRUE(q.peers.empty());
  }
  EXPECT_EQ(compare_exit_code(report), 0);
}

TEST(CompareScene, TheScenesToleranceReplacesTheDefault) {
  const std::string text = R"({"hedra_scene": 1,
    "shapes": {"ball": {"type": "sphere", "radius": 1}},
    "bodies": {"p": {"shape": "ball"}, "q": {"shape": "ball", "position": [3, 4, 0]}},
    "queries": [{"a": "p", "b": "q", "type": "distance",
                 "expect": {"distance": 3, "normal": [3, 4, 0], "tolerance": 0.25, "angle_tolerance": 0.5}}]})";
  const std::optional<LoadedScene> loaded = load(text);
  ASSERT_TRUE(loaded);
  CompareOptions options;
  options.with_peers = false;
  const CompareReport report = compare_scene(*loaded, options);
  ASSERT_EQ(report.queries.size(), 1u);
  EXPECT_TRUE(report.queries[0].reference.tolerance_from_scene);
  EXPECT_EQ(report.queries[0].reference.tolerance, 0.25);
  EXPECT_EQ(report.queries[0].reference.angle_tolerance, 0.5);
}

// ---- continuous queries ------------------------------------------------------

// A ball (radius 0.5) moving 6 along x into a unit box at the origin: first
// contact at t = (3 - 1.5) / 6 = 0.25, cast and toi; a ray along x from
// x = -4 enters the box at fraction 3/8; the same ball passing 1e-6 over the
// box's top face, a flat grazing miss the reference's trace cannot finish.
const char* kSweepScene = R"({"hedra_scene": 1, "name": "sweep",
  "shapes": {"ball": {"type": "sphere", "radius": 0.5}, "box": {"type": "box", "half_extents": [1, 1, 1]}},
  "bodies": {"ball": {"shape": "ball", "position": [-3, 0, 0], "end_position": [3, 0, 0]},
             "box": {"shape": "box"},
             "skimmer": {"shape": "ball", "position": [-3, 0, 1.500001], "end_position": [3, 0, 1.500001]}},
  "queries": [{"a": "ball", "b": "box", "type": "cast"},
              {"a": "ball", "b": "box", "type": "toi"},
              {"type": "raycast", "body": "box", "origin": [-4, 0.5, 0.5], "direction": [8, 0, 0]},
              {"a": "skimmer", "b": "box", "type": "cast"}]})";

TEST(CompareContinuous, HedraIsJudgedAgainstTheFirstContact) {
  const std::optional<LoadedScene> loaded = load(kSweepScene);
  ASSERT_TRUE(loaded);
  CompareOptions options;
  options.with_peers = false;
  const CompareReport report = compare_scene(*loaded, options);
  ASSERT_EQ(report.queries.size(), 4u);
  for (std::size_t i = 0; i < 3; ++i) {
    SCOPED_TRACE("query " + std::to_string(i));
    const QueryComparison& q = report.queries[i];
    ASSERT_TRUE(q.reference.continuous);
    const hedra::reference::FirstContact& f = q.reference.continuous->contact;
    EXPECT_TRUE(q.reference.continuous->available());
    const double expected = i < 2 ? 0.25 : 3.0 / 8.0;
    EXPECT_LE(f.early, expected + 1e-12);
    EXPECT_GE(f.late, expected - 1e-12);
    EXPECT_LT(f.late - f.early, 1e-9);
    EXPECT_EQ(q.hedra.judgement.verdict, Verdict::agree) << q.hedra.judgement.detail;
    ASSERT_TRUE(q.hedra.answer.fraction);
    EXPECT_NEAR(*q.hedra.answer.fraction, expected, 1e-9);
  }
  // The flat grazing miss: the trace runs out, hedra's miss is not judged
  // and does not fail the command.
  const QueryComparison& graze = report.queries[3];
  EXPECT_TRUE(graze.reference.continuous->contact.exhausted);
  EXPECT_EQ(graze.hedra.judgement.verdict, Verdict::no_reference);
  EXPECT_EQ(compare_exit_code(report), 0);
  const std::string text = format_compare_text(report);
  EXPECT_NE(text.find("reference unavailable: the trace ran out of steps"), std::string::npos) << text;
  EXPECT_NE(text.find("agrees with the exact reference on 3 of 4 queries; 1 not judged"), std::string::npos) << text;
  const nlohmann::json json = nlohmann::json::parse(format_compare_json(report));
  const nlohmann::json& first = json["queries"][0]["reference"]["first_contact"];
  for (const char* key : {"available", "initially", "contact", "early", "late", "rate", "steps", "max_steps"})
    EXPECT_TRUE(first.contains(key)) << key;
  for (const char* key : {"hit", "fraction", "tunnelled", "false_hit", "fraction_error", "verdict", "distance"})
    EXPECT_TRUE(json["queries"][1]["hedra"].contains(key)) << key;
  EXPECT_EQ(json["queries"][1]["hedra"]["tunnelled"], false);
  EXPECT_EQ(json["queries"][3]["reference"]["first_contact"]["available"], false);
  EXPECT_EQ(json["summary"]["hedra_not_judged"], 1);
  EXPECT_EQ(json["summary"]["hedra_agrees"], true);
}

TEST(CompareContinuous, ALateMissedOrFalseHitFailsHedra) {
  const std::optional<LoadedScene> loaded = load(kSweepScene);
  ASSERT_TRUE(loaded);
  CompareOptions options;
  options.with_peers = false;
  CompareReport report = compare_scene(*loaded, options);
  QueryComparison& q = report.queries[1];
  auto rejudge = [&](bool hit, double fraction) {
    q.hedra.answer.intersecting = hit;
    q.hedra.answer.fraction = fraction;
    q.hedra.judgement = judge(QueryType::toi, q.reference, q.hedra.answer);
    return q.hedra.judgement;
  };
  // 1e-6 later than the contact (6e-6 along the motion, tolerance 1e-9 of the size): tunnelled.
  Judgement j = rejudge(true, 0.25 + 1e-6);
  EXPECT_EQ(j.verdict, Verdict::disagree);
  ASSERT_TRUE(j.contact);
  EXPECT_TRUE(j.contact->tunnelled);
  EXPECT_FALSE(j.contact->through);
  EXPECT_EQ(compare_exit_code(report), 1);
  j = rejudge(false, 1.0);  // a miss of a certain contact: through
  EXPECT_TRUE(j.contact->tunnelled && j.contact->through);
  j = rejudge(true, 0.2);  // early by 0.3 along the motion: no tunnelling, but not within the tolerance
  EXPECT_EQ(j.verdict, Verdict::disagree);
  EXPECT_FALSE(j.contact->tunnelled);
  EXPECT_NEAR(j.contact->error, 0.3 / std::sqrt(3.0), 1e-9);  // relative to the size: the box's reach
  j = rejudge(true, 0.25);
  EXPECT_EQ(j.verdict, Verdict::agree) << j.detail;
  EXPECT_EQ(compare_exit_code(report), 0);
  // A hit on the grazing miss is a false hit even though the trace ran out.
  QueryComparison& graze = report.queries[3];
  graze.hedra.answer.intersecting = true;
  graze.hedra.answer.fraction = 0.5;
  graze.hedra.judgement = judge(QueryType::cast, graze.reference, graze.hedra.answer);
  EXPECT_EQ(graze.hedra.judgement.verdict, Verdict::disagree) << graze.hedra.judgement.detail;
  EXPECT_TRUE(graze.hedra.judgement.contact && graze.hedra.judgement.contact->false_hit);
  EXPECT_EQ(compare_exit_code(report), 1);
}

#if defined(HEDRA_COMPARE_WITH_PEERS)

namespace peers = hedra::peers;

class Fixed final : public peers::PreparedPair {
 public:
  enum class Kind { abort, hang, unsupported, wrong, right };
  Fixed(Kind kind, const peers::PeerPair& pair) : kind_(kind), pair_(pair) {}
  peers::PeerResult query(peers::PeerQuery query) override {
    peers::PeerResult r;
    r.distance = NAN;
    switch (kind_) {
      case Kind::abort:
        std::abort();
      case Kind::hang:
        std::this_thread::sleep_for(std::chrono::seconds(30));
        break;
      case Kind::unsupported:
        r.status = "unsupported: a test peer with no such shape";
        return r;
      case Kind::wrong:
      case Kind::right: {
        // The two balls' closed form (radius 1 each), or 0.1 too far.
        const Eigen::Vector3d d = pair_.pose_b.translation - pair_.pose_a.translation;
        r.supported = r.ok = true;
        r.status = "ok";
        r.distance = d.norm() - 2.0 + (kind_ == Kind::wrong ? 0.1 : 0.0);
        r.intersecting = r.distance < 0.0;
        if (query == peers::PeerQuery::intersect) return r;
        if (query == peers::PeerQuery::distance) r.distance = std::max(r.distance, 0.0);
        r.has_distance = true;
        r.normal = d.normalized();
        r.point_a = pair_.pose_a.translation + r.normal;
        r.point_b = r.point_a + r.distance * r.normal;
        return r;
      }
    }
    return r;
  }

 private:
  Kind kind_;
  peers::PeerPair pair_;
};

std::vector<peers::PeerMethod> fabricated_methods() {
  return {
      {"aborts", "calls abort()",
       [](const peers::PeerPair& p) -> std::unique_ptr<peers::PreparedPair> {
         return std::make_unique<Fixed>(Fixed::Kind::abort, p);
       }},
      {"hangs", "sleeps 30 s",
       [](const peers::PeerPair& p) -> std::unique_ptr<peers::PreparedPair> {
         return std::make_unique<Fixed>(Fixed::Kind::hang, p);
       }},
      {"cannot", "unsupported",
       [](const peers::PeerPair& p) -> std::unique_ptr<peers::PreparedPair> {
         return std::make_unique<Fixed>(Fixed::Kind::unsupported, p);
       }},
      {"wrong", "0.1 too far",
       [](const peers::PeerPair& p) -> std::unique_ptr<peers::PreparedPair> {
         return std::make_unique<Fixed>(Fixed::Kind::wrong, p);
       }},
      {"right", "the closed form",
       [](const peers::PeerPair& p) -> std::unique_ptr<peers::PreparedPair> {
         return std::make_unique<Fixed>(Fixed::Kind::right, p);
       }},
  };
}

TEST(CompareScene, CrashingHangingUnsupportedAndWrongPeersAreReportedNotFailures) {
  const std::optional<LoadedScene> loaded = load(kBallsScene);
  ASSERT_TRUE(loaded);
  CompareOptions options;
  options.peer_timeout_seconds = 0.2;
  const CompareReport report = compare_scene(*loaded, options, fabricated_methods());
  EXPECT_TRUE(report.peers_run);
  ASSERT_EQ(report.queries.size(), 3u);
  for (const QueryComparison& q : report.queries) {
    SCOPED_TRACE("query " + std::to_string(q.index));
    ASSERT_EQ(q.peers.size(), 5u);
    EXPECT_EQ(q.hedra.judgement.verdict, Verdict::agree) << q.hedra.judgement.detail;
    EXPECT_EQ(q.peers[0].judgement.verdict, Verdict::failed);
    EXPECT_EQ(q.peers[0].answer.status.rfind("crashed", 0), 0u) << q.peers[0].answer.status;
    EXPECT_EQ(q.peers[1].judgement.verdict, Verdict::failed);
    EXPECT_EQ(q.peers[1].answer.status.rfind("timeout", 0), 0u) << q.peers[1].answer.status;
    EXPECT_EQ(q.peers[2].judgement.verdict, Verdict::unsupported);
    EXPECT_EQ(q.peers[2].answer.time_ns, 0.0) << "no time for a question not posed";
    EXPECT_EQ(q.peers[4].judgement.verdict, Verdict::agree) << q.peers[4].judgement.detail;
    EXPECT_GT(q.peers[4].answer.time_ns, 0.0);
  }
  // 0.1 too far: wrong on both distances, right on the intersect boolean.
  EXPECT_EQ(report.queries[0].peers[3].judgement.verdict, Verdict::disagree);
  EXPECT_EQ(report.queries[1].peers[3].judgement.verdict, Verdict::disagree);
  EXPECT_EQ(report.queries[2].peers[3].judgement.verdict, Verdict::agree);
  // The right peer's normal matches hedra's.
  ASSERT_TRUE(report.queries[0].peers[4].normal_angle_to_hedra.has_value());
  EXPECT_LT(*report.queries[0].peers[4].normal_angle_to_hedra, 1e-12);
  EXPECT_EQ(compare_exit_code(report), 0);
  // Both output forms say so.
  const std::string text = format_compare_text(report);
  EXPECT_NE(text.find("aborts failed: crashed"), std::string::npos) << text;
  EXPECT_NE(text.find("methods disagree; the reference sides with: hedra,"), std::string::npos) << text;
  const nlohmann::json json = nlohmann::json::parse(format_compare_json(report));
  EXPECT_EQ(json["queries"][0]["peers"][1]["verdict"], "failed");
  EXPECT_EQ(json["summary"]["verdicts"]["wrong"]["disagree"], 2);
  EXPECT_EQ(json["summary"]["hedra_agrees"], true);
}

// Continuous peers: one aborting, one tunnelling (its hit 0.1 after the
// first contact), one missing, one right (the closed form of kSweepScene).
class FixedSweep final : public peers::PreparedSweep {
 public:
  enum class Kind { abort, late, miss, right };
  explicit FixedSweep(Kind kind) : kind_(kind) {}
  peers::ToiPeerResult query() override {
    if (kind_ == Kind::abort) std::abort();
    peers::ToiPeerResult r;
    r.supported = r.ok = true;
    r.status = "ok";
    r.hit = kind_ != Kind::miss;
    r.fraction = kind_ == Kind::late ? 0.35 : kind_ == Kind::right ? 0.25 : 1.0;
    return r;
  }

 private:
  Kind kind_;
};

template <FixedSweep::Kind kind>
std::unique_ptr<peers::PreparedSweep> fixed_sweep(const peers::SweepPair&) {
  return std::make_unique<FixedSweep>(kind);
}

TEST(CompareContinuous, ATunnellingPeerIsCountedNotAFailure) {
  const std::optional<LoadedScene> loaded = load(kSweepScene);
  ASSERT_TRUE(loaded);
  const std::vector<peers::ContinuousPeerMethod> sweeps = {
      {"sweep_aborts", "calls abort()", true, fixed_sweep<FixedSweep::Kind::abort>},
      {"sweep_late", "0.1 after the contact", true, fixed_sweep<FixedSweep::Kind::late>},
      {"sweep_misses", "no hit", true, fixed_sweep<FixedSweep::Kind::miss>},
      {"sweep_right", "the closed form", true, fixed_sweep<FixedSweep::Kind::right>}};
  const CompareReport report = compare_scene(*loaded, CompareOptions{}, fabricated_methods(), sweeps);
  EXPECT_TRUE(report.peers_run);
  for (std::size_t i = 0; i < 2; ++i) {  // the cast and the toi
    SCOPED_TRACE("query " + std::to_string(i));
    const QueryComparison& q = report.queries[i];
    ASSERT_EQ(q.peers.size(), 4u) << "continuous queries go to the continuous peers only";
    EXPECT_EQ(q.hedra.judgement.verdict, Verdict::agree) << q.hedra.judgement.detail;
    EXPECT_EQ(q.peers[0].judgement.verdict, Verdict::failed);
    EXPECT_EQ(q.peers[0].answer.status.rfind("crashed", 0), 0u) << q.peers[0].answer.status;
    EXPECT_EQ(q.peers[1].judgement.verdict, Verdict::disagree);
    ASSERT_TRUE(q.peers[1].judgement.contact);
    EXPECT_TRUE(q.peers[1].judgement.contact->tunnelled);
    EXPECT_TRUE(q.peers[1].judgement.contact->through);  // 0.6 along the motion
    EXPECT_TRUE(q.peers[2].judgement.contact->tunnelled);
    EXPECT_EQ(q.peers[3].judgement.verdict, Verdict::agree) << q.peers[3].judgement.detail;
  }
  EXPECT_EQ(compare_exit_code(report), 0) << "a tunnelling peer is reported, never a failure";
  const std::string text = format_compare_text(report);
  EXPECT_NE(text.find("sweep_late disagree: hit at 0.35: tunnelled"), std::string::npos) << text;
  const nlohmann::json json = nlohmann::json::parse(format_compare_json(report));
  EXPECT_EQ(json["queries"][0]["peers"][1]["tunnelled"], true);
  // The cast and the toi (tunnelled), the ray (0.35: early by 0.2 along it), the flat graze (a false hit).
  EXPECT_EQ(json["summary"]["verdicts"]["sweep_late"]["disagree"], 4);
  EXPECT_EQ(json["summary"]["hedra_agrees"], true);
}

#endif

// ---- the subcommand ---------------------------------------------------------

using CompareCli = HedraCli;

TEST_F(CompareCli, JsonIsOneWellFormedDocumentWithEveryMethodsVerdict) {
  const std::string path = write("balls.json", kBallsScene);
  const nlohmann::json doc = run_json({"compare", path, "--json"});
  ASSERT_TRUE(doc.is_object());
  EXPECT_EQ(doc["scene"], "balls");
  ASSERT_EQ(doc["queries"].size(), 3u);
  const nlohmann::json& q0 = doc["queries"][0];
  EXPECT_EQ(q0["type"], "distance");
  EXPECT_EQ(q0["reference"]["ok"], true);
  EXPECT_NEAR(q0["reference"]["distance"].get<double>(), 3.0, 1e-14);
  EXPECT_EQ(q0["reference"]["intersecting"], false);
  EXPECT_EQ(q0["hedra"]["verdict"], "agree");
  EXPECT_NEAR(q0["hedra"]["distance"].get<double>(), 3.0, 1e-12);
  const nlohmann::json& q1 = doc["queries"][1];
  EXPECT_NEAR(q1["reference"]["distance"].get<double>(), -0.5, 1e-14);
  EXPECT_EQ(q1["reference"]["normal_unique"], true);
  EXPECT_EQ(doc["summary"]["hedra_agrees"], true);
  EXPECT_EQ(doc["summary"]["verdicts"]["hedra"]["agree"], 3);
#if defined(HEDRA_COMPARE_WITH_PEERS)
  EXPECT_EQ(doc["peers_built"], true);
  ASSERT_EQ(q0["peers"].size(), hedra::peers::peer_methods().size());
  for (const nlohmann::json& query : doc["queries"]) {
    for (const nlohmann::json& p : query["peers"]) {
      for (const char* key : {"method", "supported", "ok", "status", "distance", "normal", "point_a", "point_b",
                              "time_ns", "normal_angle_to_hedra", "verdict", "detail"})
        EXPECT_TRUE(p.contains(key)) << key;
      const std::string verdict = p["verdict"];
      EXPECT_TRUE(verdict == "agree" || verdict == "disagree" || verdict == "partial" || verdict == "unsupported" ||
                  verdict == "failed")
          << verdict;
    }
  }
  // Bullet in double precision gets two unit balls exactly.
  for (const nlohmann::json& p : q0["peers"])
    if (p["method"] == "bullet_f64_signed") {
      EXPECT_EQ(p["verdict"], "agree") << p.dump();
    }
#else
  EXPECT_EQ(doc["peers_built"], false);
  EXPECT_TRUE(q0["peers"].empty());
#endif
}

// Every method is timed the same way (warm, repeated, the median), and the
// output says how; a ray is labelled ray-<body>, as `query` and `check` do.
TEST_F(CompareCli, TimingIsStatedAndRaysAreLabelledAsElsewhere) {
  const std::string path = write("ray.json", R"({"hedra_scene": 1, "name": "ray",
        "shapes": {"crate": {"type": "box", "half_extents": [1, 1, 1]}},
        "bodies": {"crate": {"shape": "crate", "position": [5, 0, 0]}},
        "queries": [{"type": "raycast", "body": "crate", "origin": [0, 0, 0], "direction": [10, 0, 0]}]})");
  const RunResult r = run({"compare", path, "--no-peers"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("times: warm (1 untimed call first), median of 21 timed calls, every method alike"),
            std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("[0] ray-crate raycast"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("crate-crate"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("precision: each method is judged at the precision it computes in"), std::string::npos);
  const nlohmann::json doc = run_json({"compare", path, "--no-peers", "--json", "--repeat", "3"});
  EXPECT_EQ(doc["timed_calls"], 3);
  EXPECT_EQ(doc["queries"][0]["hedra"]["precision"], "double");
}

TEST_F(CompareCli, TableNamesEveryMethodAndTheOutcome) {
  const std::string path = write("balls.json", kBallsScene);
  const RunResult r = run({"compare", path});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("hedra agrees with the exact reference on all 3 queries"), std::string::npos) << r.out;
#if defined(HEDRA_COMPARE_WITH_PEERS)
  for (const hedra::peers::PeerMethod& m : hedra::peers::peer_methods())
    EXPECT_EQ(count_lines(r.out, std::string("  ") + m.name + " "), 4) << m.name;  // 3 queries + the summary
#else
  EXPECT_NE(r.out.find("peers not built"), std::string::npos) << r.out;
#endif
  const RunResult alone = run({"compare", path, "--no-peers"});
  EXPECT_EQ(alone.exit_code, 0);
  EXPECT_EQ(count_lines(alone.out, "  ccd_gjk "), 0);
}

#if defined(HEDRA_COMPARE_WITH_PEERS)
TEST_F(CompareCli, APeerThatCannotPoseTheQuestionSaysUnsupported) {
  // FCL has no margin shapes: both FCL methods say so, nothing is faked,
  // and hedra's agreement alone decides the exit code.
  const std::string path = write("soft.json", R"({"hedra_scene": 1,
    "shapes": {"soft": {"type": "box", "half_extents": [1, 1, 1], "margin": 0.25}},
    "bodies": {"p": {"shape": "soft"}, "q": {"shape": "soft", "position": [3, 0, 0]}},
    "queries": [{"a": "p", "b": "q", "type": "distance"}]})");
  const nlohmann::json doc = run_json({"compare", path, "--json"});
  const nlohmann::json& q = doc["queries"][0];
  EXPECT_NEAR(q["reference"]["distance"].get<double>(), 0.5, 1e-14);
  EXPECT_EQ(q["hedra"]["verdict"], "agree");
  int unsupported = 0;
  for (const nlohmann::json& p : q["peers"]) {
    const std::string method = p["method"];
    if (method.rfind("fcl_", 0) == 0) {
      EXPECT_EQ(p["verdict"], "unsupported");
      EXPECT_EQ(p["supported"], false);
      EXPECT_TRUE(p["distance"].is_null());
      EXPECT_NE(p["detail"].get<std::string>().find("margin"), std::string::npos);
      ++unsupported;
    }
  }
  EXPECT_EQ(unsupported, 2);
}
#endif

TEST_F(CompareCli, BadInputIsReportedExactlyAsByQuery) {
  const std::string bad = write("bad.json", R"({"hedra_scene": 1, "shapes": {"s": {"type": "sphere", "radius": -1}},
    "bodies": {"p": {"shape": "s"}}, "queries": []})");
  const RunResult query = run({"query", bad});
  EXPECT_EQ(query.exit_code, 2);
  const RunResult compare = expect_bad({"compare", bad, "--json"}, {"bad.json", "shapes.s.radius"});
  EXPECT_EQ(compare.err, query.err);
  expect_bad({"compare", (work_ / "missing.json").string()}, {"missing.json"});
  expect_bad({"compare", bad, "--repeat", "0"}, {"repeat"});
  expect_bad({"compare"}, {"scene"});
}

}  // namespace
