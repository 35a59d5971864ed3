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

Judgement judge(QueryType type, const ReferenceAnswer& reference, const MethodAnswer& answer) {
  Judgement j;
  if (is_continuous(type)) {  // raycast, cast, toi: judged by `hedra check`, not here
    j.verdict = Verdict::unsupported;
    j.detail = std::string("continuous query (") + to_string(type) + "): not compared";
    return j;
  }
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
  const double tolerance = reference.tolerance;

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
          if (!(angle <= reference.angle_tolerance)) {
            add(problems, said_normal + " > " + number(reference.angle_tolerance) + " rad)");
          } else {
            add(checks, said_normal + " <= " + number(reference.angle_tolerance) + " rad)");
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

ReferenceAnswer reference_answer(const BuiltScene& built, std::size_t index) {
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

MethodAnswer peer_answer(const peers::PeerMethod& method, QueryType type, const peers::PeerResult& result) {
  MethodAnswer m;
  m.method = method.name;
  m.description = method.description;
  m.supported = result.supported;
  m.ok = result.ok;
  m.status = result.status;
  m.intersecting = result.intersecting;
  // No time for a question the peer could not pose.
  m.time_ns = result.supported && std::isfinite(result.time_ns) ? result.time_ns : 0.0;
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

CompareReport compare_scene(const LoadedScene& loaded, const CompareOptions& options,
                            const std::vector<peers::PeerMethod>& methods) {
  CompareReport report = compare_hedra(loaded, options);
  report.peers_built = true;
  report.peers_run = options.with_peers && !methods.empty();
  if (!report.peers_run) return report;

  const Scene& scene = *loaded.scene;
  const BuiltScene& built = loaded.built;
  std::vector<peers::PeerPair> pairs;
  for (const QuerySpec& query : scene.queries) {
    pairs.push_back({*built.shapes[scene.bodies[query.a].shape], built.poses[query.a],
                     *built.shapes[scene.bodies[query.b].shape], built.poses[query.b]});
  }
  auto peer_query = [](QueryType type) {
    switch (type) {
      case QueryType::intersect:
        return peers::PeerQuery::intersect;
      case QueryType::distance:
        return peers::PeerQuery::distance;
      case QueryType::penetration:
      case QueryType::contact:
        break;
    }
    return peers::PeerQuery::penetration;
  };
  const std::size_t method_count = methods.size();
  const int repeat = std::max(options.repeat, 1);
  // One call per (query, method), run in forked children: the conversion
  // (prepare) happens there too, since a peer may crash while converting.
  auto call = [&](std::size_t k) {
    const std::size_t qi = k / method_count;
    const peers::PeerMethod& method = methods[k % method_count];
    const std::unique_ptr<peers::PreparedPair> prepared = method.prepare(pairs[qi]);
    const peers::PeerQuery query = peer_query(scene.queries[qi].type);
    peers::PeerResult result;
    std::vector<double> times;
    for (int r = 0; r < repeat; ++r) {
      const Clock::time_point start = Clock::now();
      peers::PeerResult answer = prepared->query(query);
      times.push_back(elapsed_ns(start, Clock::now()));
      result = std::move(answer);
    }
    result.time_ns = median(std::move(times));
    return result;
  };
  peers::IsolationSettings isolation;
  isolation.timeout_seconds = options.peer_timeout_seconds;
  const std::vector<peers::PeerResult> results =
      peers::run_isolated(call, scene.queries.size() * method_count, isolation);

  for (std::size_t k = 0; k < results.size(); ++k) {
    QueryComparison& q = report.queries[k / method_count];
    const QueryType type = scene.queries[q.index].type;
    q.peers.push_back(
        judged(type, q.reference, peer_answer(methods[k % method_count], type, results[k]), q.hedra.answer.normal));
  }
  return report;
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

int compare_exit_code(const CompareReport& report) {
  for (const QueryComparison& q : report.queries)
    if (q.hedra.judgement.verdict != Verdict::agree &&
        !(report.scene && is_continuous(report.scene->queries[q.index].type)))  // continuous: not judged here
      return kExitCheckFailed;
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
  const std::string distance = a.distance ? shortest(*a.distance) : "-";
  char line[512];
  std::snprintf(line, sizeof line, "  %-19s %-12s %-5s %-22s %-9s %-9s %-9s %-32s %-32s %9s\n", a.method.c_str(),
                to_string(j.judgement.verdict), a.supported && a.ok ? (a.intersecting ? "yes" : "no") : "-",
                distance.c_str(), optional_number(j.judgement.distance_error).c_str(),
                optional_number(j.judgement.normal_angle).c_str(),
                peer ? optional_number(j.normal_angle_to_hedra).c_str() : "", short_vector(a.point_a).c_str(),
                short_vector(a.point_b).c_str(), (a.time_ns > 0.0 ? format_time(a.time_ns) : std::string("-")).c_str());
  text += line;
}

}  // namespace

std::string format_compare_text(const CompareReport& report) {
  const Scene& scene = *report.scene;
  std::string text = "scene " + scene.name + " (" + scene.file + "): " + std::to_string(scene.queries.size()) +
                     (scene.queries.size() == 1 ? " query" : " queries") + "\n";
  if (!report.peers_built) {
    text += std::string(kPeersNotBuilt) + "\n";
  } else if (!report.peers_run) {
    text += "peers not run: hedra is compared with the exact reference only\n";
  }
  text +=
      "verdicts against the exact reference (tools/reference): agree, disagree, partial (boolean only), "
      "unsupported, failed (error, crash or timeout)\n";
  for (const QueryComparison& q : report.queries) {
    const QuerySpec& spec = scene.queries[q.index];
    const reference::ExactResult& e = q.reference.exact;
    text += "\n[" + std::to_string(q.index) + "] " + scene.bodies[spec.a].name + "-" + scene.bodies[spec.b].name + " " +
            to_string(spec.type) + ": reference ";
    if (e.ok) {
      const std::optional<bool> hit = q.reference.intersecting();
      text += "distance " + shortest(e.distance) + " (error bound " + number(e.error_bound) + ", tolerance " +
              number(q.reference.tolerance) + (q.reference.tolerance_from_scene ? " from the scene" : "") +
              "), normal " + vector_text(e.normal) + (e.normal_unique ? " (unique)" : " (not unique: not compared)") +
              ", intersecting " + (hit ? (*hit ? "true" : "false") : "either (touching within the tolerance)") + "\n";
    } else {
      text += "failed: " + e.reason + "\n";
    }
    char header[512];
    std::snprintf(header, sizeof header, "  %-19s %-12s %-5s %-22s %-9s %-9s %-9s %-32s %-32s %9s\n", "method",
                  "verdict", "hit", "distance", "error", "angle", "to hedra", "point_a", "point_b", "time");
    text += header;
    text_row(text, q.hedra, false);
    for (const JudgedAnswer& p : q.peers) text_row(text, p, true);
    auto explain = [&](const JudgedAnswer& j) {
      const Verdict v = j.judgement.verdict;
      if (v != Verdict::agree) text += "    " + j.answer.method + " " + to_string(v) + ": " + j.judgement.detail + "\n";
    };
    explain(q.hedra);
    for (const JudgedAnswer& p : q.peers) explain(p);
    std::string right, wrong;
    if (split(q, right, wrong)) text += "    methods disagree; the reference sides with: " + right + "\n";
  }

  text += "\nverdicts per method (agree / disagree / partial / unsupported / failed / no_reference):\n";
  for (const Tally& t : tally(report)) {
    char line[160];
    std::snprintf(line, sizeof line, "  %-19s %3d / %3d / %3d / %3d / %3d / %3d\n", t.method.c_str(), t.counts[0],
                  t.counts[1], t.counts[2], t.counts[3], t.counts[4], t.counts[5]);
    text += line;
  }
  std::string failing;
  for (const QueryComparison& q : report.queries)
    if (q.hedra.judgement.verdict != Verdict::agree) failing += (failing.empty() ? "" : " ") + std::to_string(q.index);
  const std::size_t n = report.queries.size();
  if (failing.empty()) {
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
  r["description"] = a.description;
  r["supported"] = a.supported;
  r["ok"] = a.ok;
  r["status"] = a.status;
  r["intersecting"] = a.supported && a.ok ? Json(a.intersecting) : Json(nullptr);
  r["distance"] = json_number(a.distance);
  r["normal"] = json_vector(a.normal);
  r["point_a"] = json_vector(a.point_a);
  r["point_b"] = json_vector(a.point_b);
  r["time_ns"] = a.time_ns > 0.0 && std::isfinite(a.time_ns) ? Json(a.time_ns) : Json(nullptr);
  if (peer) r["normal_angle_to_hedra"] = json_number(j.normal_angle_to_hedra);
  r["verdict"] = to_string(j.judgement.verdict);
  r["detail"] = j.judgement.detail;
  r["distance_error"] = json_number(j.judgement.distance_error);
  r["normal_angle"] = json_number(j.judgement.normal_angle);
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
    if (!e.ok) {
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
