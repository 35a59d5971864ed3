// `hedra bench`'s runner: methods, timing, judging and the summaries (see
// bench.hpp for the rules).
#include "cli/bench/bench.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <hedra/collision/query.hpp>
#include <map>
#include <memory>
#include <utility>

#include "scene/timing.hpp"

#if defined(HEDRA_COMPARE_WITH_PEERS)
#  include <isolation.hpp>
#endif

namespace hedra::tool::bench {

namespace {

constexpr double kDefaultTolerance = 1e-10;  // GjkSettings' and EpaSettings' defaults
constexpr double kAngleTolerance = 1e-3;     // rad, on normals where the reference's is unique

std::string tolerance_text(double t) {
  char text[16];
  std::snprintf(text, sizeof text, "%.0e", t);
  return text;
}

double seconds_since(Clock::time_point start) { return elapsed_ns(start, Clock::now()) * 1e-9; }

// Per-call time of `call`: one calibration call, then `loops` loops of k
// calls lasting about `loop_ns` each; the median of loop time / k.
template <class Call>
double time_per_call(Call&& call, int loops, double loop_ns) {
  Clock::time_point start = Clock::now();
  call();
  const double one = std::max(elapsed_ns(start, Clock::now()), 1.0);
  const int k = static_cast<int>(std::clamp(std::ceil(loop_ns / one), 1.0, 100000.0));
  std::vector<double> samples;
  for (int l = 0; l < std::max(loops, 1); ++l) {
    start = Clock::now();
    for (int j = 0; j < k; ++j) call();
    samples.push_back(elapsed_ns(start, Clock::now()) / k);
  }
  return median(std::move(samples));
}

// Nearest-rank percentile of sorted values.
double percentile(const std::vector<double>& sorted, double p) {
  if (sorted.empty()) return 0.0;
  const std::size_t rank = static_cast<std::size_t>(std::ceil(p * static_cast<double>(sorted.size())));
  return sorted[std::min(sorted.size(), std::max<std::size_t>(rank, 1)) - 1];
}

double median_of(std::vector<double> values) { return median(std::move(values)); }

// What every hedra answer says: the method, the status and whether it is
// judged (ok), the verdict and the time.
MethodAnswer hedra_answer_head(const Method& method, collision::Status status, bool ok, bool intersecting,
                               double time_ns) {
  MethodAnswer m;
  m.method = method.name;
  m.description = method.description;
  m.supported = true;
  m.status = collision::to_string(status);
  m.ok = ok;
  m.intersecting = intersecting;
  m.time_ns = time_ns;
  return m;
}

MethodAnswer hedra_method_answer(const Method& method, const collision::PenetrationResult& r, double time_ns) {
  // Caps and invalid states are failures; `stalled` is judged by its answer.
  MethodAnswer m =
      hedra_answer_head(method, r.status, r.status == collision::Status::ok || r.status == collision::Status::stalled,
                        r.intersecting, time_ns);
  if (!std::isfinite(r.distance) || !r.normal.allFinite() || !r.point_a.allFinite() || !r.point_b.allFinite()) {
    m.ok = false;
    m.status = "non_finite";
    return m;
  }
  if (r.status == collision::Status::degenerate || r.status == collision::Status::invalid_input) return m;
  m.distance = r.distance;
  if (r.normal.squaredNorm() > 0.0) m.normal = r.normal;
  m.point_a = r.point_a;
  m.point_b = r.point_b;
  return m;
}

// distance(): as penetration's, the distance >= 0 (0 when it says the
// shapes touch or overlap: then no normal nor witnesses).
MethodAnswer hedra_method_answer(const Method& method, const collision::DistanceResult& r, double time_ns) {
  collision::PenetrationResult p;
  p.status = r.status;
  p.intersecting = r.intersecting;
  p.distance = r.distance;
  p.normal = r.normal;
  p.point_a = r.point_a;
  p.point_b = r.point_b;
  MethodAnswer m = hedra_method_answer(method, p, time_ns);
  if (r.intersecting) m.point_a = m.point_b = std::nullopt;
  return m;
}

// intersect(): the verdict alone, defined only when ok (a stall or a cap
// leaves no verdict: a failure).
MethodAnswer hedra_method_answer(const Method& method, const collision::IntersectResult& r, double time_ns) {
  return hedra_answer_head(method, r.status, r.status == collision::Status::ok, r.intersecting, time_ns);
}

std::vector<CaseResult> run_hedra(const FamilyRun& family, const Method& method, const BenchOptions& options) {
  collision::PenetrationSettings settings;
  if (!method.is_default) {
    settings.gjk.relative_tolerance = settings.gjk.absolute_tolerance = method.tolerance;
    settings.epa.relative_tolerance = settings.epa.absolute_tolerance = method.tolerance;
  }
  std::vector<CaseResult> out;
  volatile double sink = 0.0;
  for (const BenchCase& c : family.cases) {
    MethodAnswer answer;
    switch (options.query) {
      case QueryType::distance: {
        const auto query = [&] { return collision::distance(c.a, c.pose_a, c.b, c.pose_b, nullptr, settings.gjk); };
        const collision::DistanceResult r = query();
        const double t = time_per_call([&] { sink = sink + query().distance; }, options.loops, options.loop_ns);
        answer = hedra_method_answer(method, r, t);
        break;
      }
      case QueryType::intersect: {
        const auto query = [&] { return collision::intersect(c.a, c.pose_a, c.b, c.pose_b, nullptr, settings.gjk); };
        const collision::IntersectResult r = query();
        const double t =
            time_per_call([&] { sink = sink + (query().intersecting ? 1.0 : 0.0); }, options.loops, options.loop_ns);
        answer = hedra_method_answer(method, r, t);
        break;
      }
      default: {
        const auto query = [&] { return collision::penetration(c.a, c.pose_a, c.b, c.pose_b, nullptr, settings); };
        const collision::PenetrationResult r = query();
        const double t = time_per_call([&] { sink = sink + query().distance; }, options.loops, options.loop_ns);
        answer = hedra_method_answer(method, r, t);
        break;
      }
    }
    out.push_back(judge_case(c, method, std::move(answer), options.fail_tolerance, options.query));
  }
  return out;
}

#if defined(HEDRA_COMPARE_WITH_PEERS)
peers::PeerQuery peer_query(QueryType query) {
  switch (query) {
    case QueryType::distance:
      return peers::PeerQuery::distance;
    case QueryType::intersect:
      return peers::PeerQuery::intersect;
    default:
      return peers::PeerQuery::penetration;
  }
}

std::vector<CaseResult> run_peer(const FamilyRun& family, const Method& method, const BenchOptions& options) {
  const peers::PeerMethod& peer = *method.peer;
  const peers::PeerQuery asked = peer_query(options.query);
  std::vector<peers::PeerPair> pairs;
  for (const BenchCase& c : family.cases) pairs.push_back({c.a, c.pose_a, c.b, c.pose_b});
  // In the child: convert, answer once, then time the query alone.
  auto call = [&](std::size_t k) {
    const std::unique_ptr<peers::PreparedPair> prepared = peer.prepare(pairs[k]);
    peers::PeerResult result = prepared->query(asked);
    if (result.supported) {
      result.time_ns = time_per_call([&] { prepared->query(asked); }, options.loops, options.loop_ns);
    }
    return result;
  };
  peers::IsolationSettings isolation;
  // The timeout covers the timed loops too (loops * loop_ns, plus slow
  // calibration calls on large hulls).
  isolation.timeout_seconds = options.peer_timeout_seconds;
  const std::vector<peers::PeerResult> results = peers::run_isolated(call, pairs.size(), isolation);
  std::vector<CaseResult> out;
  for (std::size_t k = 0; k < results.size(); ++k) {
    out.push_back(judge_case(family.cases[k], method, peer_answer(peer, options.query, results[k]),
                             options.fail_tolerance, options.query));
  }
  return out;
}
#endif

}  // namespace

std::vector<double> hedra_tolerances(bool quick) {
  if (quick) return {1e-3, 1e-6, 1e-12};
  return {1e-3, 1e-4, 1e-6, 1e-8, 1e-12};
}

std::vector<QueryType> bench_queries() { return {QueryType::penetration, QueryType::distance, QueryType::intersect}; }

std::optional<QueryType> find_bench_query(const std::string& name) {
  for (const QueryType q : bench_queries())
    if (name == to_string(q)) return q;
  return std::nullopt;
}

std::vector<Method> all_methods(bool quick, QueryType query) {
  std::vector<Method> methods;
  Method hedra;
  hedra.name = "hedra";
  hedra.description = query == QueryType::distance    ? "hedra: distance(), GJK (default tolerance 1e-10)"
                      : query == QueryType::intersect ? "hedra: intersect(), GJK to the first separating axis"
                                                      : "hedra: GJK, then EPA when the cores overlap (default "
                                                        "tolerance 1e-10)";
  hedra.is_hedra = true;
  hedra.is_default = true;
  hedra.tolerance = kDefaultTolerance;
  methods.push_back(hedra);
  // intersect() has no tolerance to sweep but that of touching pairs.
  if (query != QueryType::intersect) {
    for (const double t : hedra_tolerances(quick)) {
      Method m;
      m.name = "hedra@" + tolerance_text(t);
      m.description = "hedra with GJK" + std::string(query == QueryType::penetration ? " and EPA" : "") +
                      " tolerances " + tolerance_text(t);
      m.is_hedra = true;
      m.tolerance = t;
      methods.push_back(m);
    }
  }
#if defined(HEDRA_COMPARE_WITH_PEERS)
  for (const peers::PeerMethod& peer : peers::peer_methods()) {
    // libccd's plain GJK answers the boolean only: nothing to measure an
    // error on, and its time is that of another question (except under
    // intersect, where it is the question).
    if (std::string(peer.name) == "ccd_gjk" && query != QueryType::intersect) continue;
    Method m;
    m.name = peer.name;
    m.description = peer.description;
    m.peer = &peer;
    methods.push_back(m);
  }
#endif
  return methods;
}

bool asks_about(QueryType query, const BenchCase& c, double fail_tolerance) {
  if (query != QueryType::distance) return true;
  const ReferenceAnswer& r = c.reference;
  const double tolerance = r.tolerance_from_scene ? r.tolerance : r.exact.error_bound + fail_tolerance * r.pair_size;
  return r.exact.ok && r.exact.distance > tolerance;
}

void keep_asked_cases(FamilyRun& family, const BenchOptions& options) {
  std::vector<BenchCase> kept;
  for (BenchCase& c : family.cases) {
    if (asks_about(options.query, c, options.fail_tolerance)) {
      kept.push_back(std::move(c));
    } else {
      ++family.skipped;
    }
  }
  family.cases = std::move(kept);
}

CaseResult judge_case(const BenchCase& c, const Method& method, MethodAnswer answer, double fail_tolerance,
                      QueryType query) {
  ReferenceAnswer reference = c.reference;
  const double requested = method.is_hedra ? method.tolerance : 0.0;
  if (!reference.tolerance_from_scene) {
    reference.tolerance = reference.exact.error_bound + std::max(fail_tolerance, 2.0 * requested) * reference.pair_size;
  }
  // A tolerance looser than the benchmark's asks for the depth only: EPA or
  // GJK stopping that far short may end on a feature whose normal is far
  // from the true one while the distance along it is within the tolerance
  // (a flat minimum, or a small body beside a large one, whose size sets
  // the tolerance). Methods held to the benchmark's tolerance (the peers,
  // hedra's default and tighter) are held to the normal too.
  reference.angle_tolerance = 2.0 * requested > fail_tolerance ? M_PI : kAngleTolerance;
  CaseResult r;
  r.tolerance = reference.tolerance;
  // judge() holds the rules per query: intersect compares the verdict only;
  // distance compares against max(sd, 0) (sd > 0 on the pairs it is asked).
  r.judgement = judge(query, reference, answer);
  // Failed answers that still carry a distance (hedra's best so far at a
  // cap) are measured too: they count as failures all the same.
  if (answer.distance && std::isfinite(*answer.distance)) {
    // The error: |d - sd| for polytope cores (the reference is exact up to
    // its rounding, error_bound, about 1e-14 of the size); for curved pairs
    // the distance from d to the reference's certified bracket [lower,
    // upper], about 1e-12 of the size wide, wider where the inscribed
    // polygons cannot resolve a ring of equal depths (nearly coaxial
    // cylinders and cones: up to 1e-2). An answer inside the bracket counts
    // as exact, since nothing finer is known.
    const double d = *answer.distance;
    const reference::ExactResult& e = reference.exact;
    r.abs_error = !e.curved ? std::abs(d - e.distance) : d < e.lower ? e.lower - d : d > e.upper ? d - e.upper : 0.0;
    r.rel_error = reference.pair_size > 0 ? *r.abs_error / reference.pair_size : *r.abs_error;
  }
  switch (r.judgement.verdict) {
    case Verdict::failed:
      r.failure = true;
      r.failure_kind = "failed: " + answer.status;
      break;
    case Verdict::disagree: {
      r.failure = true;
      const std::string& d = r.judgement.detail;
      r.failure_kind = d.rfind("intersecting", 0) == 0 ? "classification"
                       : d.rfind("distance", 0) == 0   ? "error"
                                                       : "normal";
      break;
    }
    default:
      break;
  }
  r.answer = std::move(answer);
  return r;
}

Summary summarize(const std::vector<CaseResult>& results) {
  Summary s;
  s.cases = results.size();
  std::vector<double> times, abs, rel, angles;
  std::map<std::string, int> kinds;
  std::map<std::string, int> unsupported;
  for (const CaseResult& r : results) {
    if (!r.answer.supported) {
      ++unsupported[r.answer.status];
      continue;
    }
    ++s.supported;
    if (r.answer.ok && r.answer.time_ns > 0) times.push_back(r.answer.time_ns);
    if (r.judgement.verdict == Verdict::partial) ++s.partial;
    if (r.abs_error) {
      ++s.answered;
      abs.push_back(*r.abs_error);
      rel.push_back(*r.rel_error);
    }
    if (r.judgement.normal_angle) angles.push_back(*r.judgement.normal_angle);
    if (r.failure) {
      ++s.failures;
      ++kinds[r.failure_kind];
    }
  }
  for (const auto& [kind, n] : kinds) s.failure_kinds.push_back(kind + " x" + std::to_string(n));
  for (const auto& [reason, n] : unsupported) s.unsupported.push_back(reason + " x" + std::to_string(n));
  std::sort(times.begin(), times.end());
  std::sort(abs.begin(), abs.end());
  std::sort(rel.begin(), rel.end());
  if (!times.empty()) {
    s.time_median_ns = median_of(times);
    s.time_p99_ns = percentile(times, 0.99);
  }
  if (!abs.empty()) {
    s.abs_median = median_of(abs);
    s.abs_p99 = percentile(abs, 0.99);
    s.abs_max = abs.back();
    s.rel_median = median_of(rel);
    s.rel_p99 = percentile(rel, 0.99);
    s.rel_max = rel.back();
  }
  if (!angles.empty()) s.angle_median = median_of(angles);
  return s;
}

std::vector<StabilityRow> stability(const FamilyRun& family, const std::vector<CaseResult>& results) {
  std::map<double, std::pair<std::vector<double>, std::size_t>> groups;  // parameter -> (errors, failures)
  for (std::size_t k = 0; k < family.cases.size() && k < results.size(); ++k) {
    const double p = family.cases[k].parameter;
    if (!std::isfinite(p)) continue;
    auto& group = groups[p];
    if (results[k].rel_error) group.first.push_back(*results[k].rel_error);
    if (results[k].failure) ++group.second;
  }
  std::vector<StabilityRow> rows;
  for (auto& [p, group] : groups) {
    StabilityRow row;
    row.parameter = p;
    row.cases = group.first.size();
    row.failures = group.second;
    if (!group.first.empty()) {
      row.rel_max = *std::max_element(group.first.begin(), group.first.end());
      row.rel_median = median_of(group.first);
    }
    rows.push_back(row);
  }
  return rows;
}

std::vector<FamilyRun> generate_families(const BenchOptions& options, std::ostream& progress) {
  std::vector<FamilyRun> runs;
  for (const FamilyInfo& info : families()) {
    if (!options.families.empty() &&
        std::find(options.families.begin(), options.families.end(), info.name) == options.families.end())
      continue;
    const Clock::time_point start = Clock::now();
    FamilyCases made = make_family(info.name, options.workload);
    FamilyRun run;
    run.name = info.name;
    run.parameter = info.parameter;
    run.cases = std::move(made.cases);
    run.dropped = made.dropped;
    run.notes = std::move(made.notes);
    run.reference_seconds = seconds_since(start);
    keep_asked_cases(run, options);
    char line[200];
    std::snprintf(line, sizeof line, "bench: %-16s %3zu cases with exact references (%.1f s)%s", info.name,
                  run.cases.size(), run.reference_seconds, run.dropped ? ", some dropped" : "");
    progress << line;
    if (run.skipped) progress << ", " << run.skipped << " not separated beyond the tolerance: not asked";
    progress << "\n" << std::flush;
    if (run.cases.empty()) continue;  // nothing asked (distance on overlapping families)
    runs.push_back(std::move(run));
  }
  return runs;
}

BenchReport run_bench(const BenchOptions& options, const std::vector<Method>& methods, std::vector<FamilyRun> families,
                      std::ostream& progress) {
  const Clock::time_point start = Clock::now();
  BenchReport report;
  report.query = options.query;
  report.methods = methods;
#if defined(HEDRA_COMPARE_WITH_PEERS)
  report.peers_built = true;
#endif
  for (FamilyRun& family : families) {
    for (const Method& method : methods) {
      const Clock::time_point method_start = Clock::now();
      std::vector<CaseResult> results;
      if (method.is_hedra) {
        results = run_hedra(family, method, options);
      }
#if defined(HEDRA_COMPARE_WITH_PEERS)
      else if (method.peer) {
        results = run_peer(family, method, options);
      }
#endif
      std::size_t failures = 0;
      for (const CaseResult& r : results) failures += r.failure ? 1 : 0;
      char line[200];
      std::snprintf(line, sizeof line, "bench: %-16s %-20s %3zu case%s, %zu failure%s (%.1f s, elapsed %.0f s)\n",
                    family.name.c_str(), method.name.c_str(), results.size(), results.size() == 1 ? "" : "s", failures,
                    failures == 1 ? "" : "s", seconds_since(method_start), seconds_since(start));
      progress << line << std::flush;
      family.results.push_back(std::move(results));
    }
  }
  report.families = std::move(families);
  report.elapsed_seconds = seconds_since(start);
  return report;
}

std::size_t hedra_failures(const BenchReport& report) {
  std::size_t n = 0;
  for (const FamilyRun& family : report.families)
    for (std::size_t m = 0; m < report.methods.size() && m < family.results.size(); ++m)
      if (report.methods[m].is_hedra)
        for (const CaseResult& r : family.results[m]) n += r.failure ? 1 : 0;
  return n;
}

}  // namespace hedra::tool::bench
