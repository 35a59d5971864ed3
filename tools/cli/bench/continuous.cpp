// hedra bench --continuous: see continuous.hpp. Order of work: generate each
// family's sweeps (seeded) and bracket their first contacts with the exact
// reference -> run hedra's queries and, in forked children, the peers', each
// timed (calls repeated until a loop lasts 20 us, the median of the loops)
// -> judge every answer against the bracket -> one row per family and method.
#include "cli/bench/continuous.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <first_contact.hpp>
#include <functional>
#include <hedra/collision/cast.hpp>
#include <hedra/collision/time_of_impact.hpp>
#include <limits>
#include <map>
#include <ostream>
#include <random>
#include <sstream>

#ifdef HEDRA_COMPARE_WITH_PEERS
#  include <continuous.hpp>  // tools/peers
#endif

namespace hedra::tool::bench {
namespace {

using collision::Shape;
using Vec = Eigen::Vector3d;
using Quat = Eigen::Quaterniond;
using reference::Motion;

struct SweepCase {
  Shape a, b;
  Motion ma, mb;
  double size = 0.0, far = 0.0;
  reference::FirstContact contact;
  bool rotates() const { return ma.angle() != 0.0 || mb.angle() != 0.0; }
};

collision::Sweep sweep_of(const Motion& m) {
  return {collision::Pose::from_quaternion(m.q0, m.p0), collision::Pose::from_quaternion(m.q1, m.p1)};
}

// ---- the families ----------------------------------------------------------

Vec random_unit(std::mt19937_64& rng) {
  std::normal_distribution<double> g(0.0, 1.0);
  return Vec(g(rng), g(rng), g(rng)).normalized();
}

Quat random_rotation(std::mt19937_64& rng) {
  std::normal_distribution<double> g(0.0, 1.0);
  return Quat(g(rng), g(rng), g(rng), g(rng)).normalized();
}

Quat turned(std::mt19937_64& rng, const Quat& q0, double angle) {
  return Quat(Eigen::AngleAxisd(angle, random_unit(rng))) * q0;
}

std::vector<Shape> projectiles(std::mt19937_64& rng, double size) {
  std::uniform_real_distribution<double> u(-size, size);
  std::vector<Vec> points;
  for (int i = 0; i < 12; ++i) points.emplace_back(u(rng), u(rng), u(rng));
  std::vector<Shape> out = {collision::Sphere{size, 0.0}, collision::Box{Vec(size, 0.6 * size, 0.8 * size), 0.0},
                            collision::Box{Vec(size, 0.6 * size, 0.8 * size), 0.1 * size},
                            collision::Capsule{0.5 * size, size, 0.0}, collision::Cylinder{0.7 * size, size, 0.0}};
  const collision::ConvexPolyhedron::BuildResult hull = collision::ConvexPolyhedron::build(points);
  if (hull.ok()) out.push_back(collision::Polyhedron{hull.polyhedron, 0.0});
  return out;
}

SweepCase sweep(const Shape& a, const Motion& ma, const Shape& b, const Motion& mb) {
  SweepCase c{a, b, ma, mb, 0.0, 0.0, {}};
  c.size = std::max(reference::reach(a), reference::reach(b));
  c.far = std::max({ma.p0.cwiseAbs().maxCoeff(), mb.p0.cwiseAbs().maxCoeff(), ma.p1.cwiseAbs().maxCoeff(),
                    mb.p1.cwiseAbs().maxCoeff()});
  return c;
}

Motion still(const Vec& p) { return {Quat::Identity(), Quat::Identity(), p, p}; }

// A plate 1e-2 thick, bodies 0.05 travelling 10 through it, at `shift`.
void plate_sweeps(std::mt19937_64& rng, const Vec& shift, bool straight_too, int per_shape, std::size_t shapes,
                  std::vector<SweepCase>& out) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const Shape plate = collision::Box{Vec(3.0, 3.0, 5e-3), 0.0};
  std::vector<Shape> bodies = projectiles(rng, 0.05);
  bodies.resize(std::min(shapes, bodies.size()));
  for (const Shape& body : bodies) {
    for (int i = 0; i < per_shape; ++i) {
      const Vec side(u(rng), u(rng), 0.0);
      const Vec start = shift + side + Vec(0, 0, -5.0), end = shift - side + Vec(0, 0, 5.0);
      const Quat q0 = random_rotation(rng);
      if (straight_too) out.push_back(sweep(body, {q0, q0, start, end}, plate, still(shift)));
      out.push_back(sweep(body, {q0, turned(rng, q0, 3.0), start, end}, plate, still(shift)));
    }
  }
}

std::vector<SweepCase> thin_plate(std::mt19937_64& rng, bool quick) {
  std::vector<SweepCase> out;
  plate_sweeps(rng, Vec::Zero(), true, quick ? 1 : 4, quick ? 3 : 6, out);
  return out;
}

std::vector<SweepCase> grazing(std::mt19937_64&, bool quick) {
  std::vector<SweepCase> out;
  const std::vector<double> sphere_gaps =
      quick ? std::vector<double>{1e-2, 0.0, -1e-3} : std::vector<double>{1e-2, 1e-6, 1e-8, 0.0, -1e-7, -1e-3};
  for (const double c : sphere_gaps)
    out.push_back(sweep(collision::Sphere{0.5, 0.0}, {Quat::Identity(), Quat::Identity(), Vec(-3, 0, 0), Vec(3, 0, 0)},
                        collision::Sphere{0.25, 0.1}, still(Vec(0, 0.85 + c, 0))));
  const Shape block = collision::Box{Vec(1.0, 1.0, 0.5), 0.0};
  const std::vector<double> face_gaps =
      quick ? std::vector<double>{1e-3, -1e-6} : std::vector<double>{1e-3, 1e-6, 0.0, -1e-6};
  for (const double c : face_gaps) {
    out.push_back(sweep(collision::Sphere{0.2, 0.0},
                        {Quat::Identity(), Quat::Identity(), Vec(-2, 0, 0.7 + c), Vec(2, 0.1, 0.7 + c)}, block,
                        still(Vec::Zero())));
    out.push_back(sweep(collision::Box{Vec(0.3, 0.3, 0.3), 0.0},
                        {Quat(Eigen::AngleAxisd(0.3, Vec::UnitZ())), Quat(Eigen::AngleAxisd(1.2, Vec::UnitZ())),
                         Vec(-2, 0, 0.8 + c), Vec(2, 0, 0.8 + c)},
                        block, still(Vec::Zero())));
  }
  return out;
}

std::vector<SweepCase> rotating_bar(std::mt19937_64&, bool quick) {
  std::vector<SweepCase> out;
  const Shape post = collision::Box{Vec(0.05, 0.05, 0.5), 0.0};
  for (const double half_length : {2.0, 1.3}) {
    for (const double turn : quick ? std::vector<double>{2.5} : std::vector<double>{1.5, 2.5, 3.1}) {
      const Motion bar{Quat::Identity(), Quat(Eigen::AngleAxisd(turn, Vec::UnitZ())), Vec::Zero(), Vec(0, 0, 0.1)};
      const Shape shape = collision::Box{Vec(half_length, 0.02, 0.02), 0.0};
      out.push_back(sweep(shape, bar, post, still(Vec(0.4, 1.5, 0))));
      out.push_back(sweep(shape, bar, post, still(Vec(-0.4, -1.5, 0))));
    }
  }
  return out;
}

std::vector<SweepCase> initial_contact(std::mt19937_64& rng, bool quick) {
  std::vector<SweepCase> out;
  const Shape box = collision::Box{Vec(1, 1, 1), 0.0};
  for (const double gap : {-0.3, -1e-6, 0.0})
    out.push_back(sweep(box, {Quat::Identity(), Quat::Identity(), Vec::Zero(), Vec(1, 0, 0)},
                        collision::Capsule{0.5, 0.5, 0.0},
                        {Quat::Identity(), Quat::Identity(), Vec(1.5 + gap, 0, 0), Vec(1.5 + gap, 0, -1)}));
  // Overlapping pairs of every projectile, spinning apart or further in.
  std::vector<Shape> shapes = projectiles(rng, 0.5);
  if (quick) shapes.resize(2);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (const Shape& s : shapes) {
    const Quat q0 = random_rotation(rng);
    out.push_back(sweep(s, {q0, turned(rng, q0, 1.0), Vec(0.2 * u(rng), 0.2 * u(rng), 0.0), Vec(2, u(rng), u(rng))},
                        collision::Sphere{0.4, 0.0}, still(Vec(0.3, 0, 0))));
  }
  return out;
}

std::vector<SweepCase> small_large(std::mt19937_64& rng, bool quick) {
  std::vector<SweepCase> out;
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const Shape block = collision::Box{Vec(1e3, 1e3, 1e3), 0.0};
  std::vector<Shape> shapes = projectiles(rng, 1e-3);
  if (quick) shapes.resize(2);
  for (const Shape& s : shapes) {
    const Quat q0 = random_rotation(rng);
    const Motion small{q0, turned(rng, q0, 2.0), Vec(u(rng), u(rng), 0.5), Vec(u(rng), u(rng), -0.5)};
    out.push_back(sweep(s, small, block, still(Vec(0, 0, -1e3))));
    out.push_back(sweep(block, still(Vec(0, 0, -1e3)), s, small));
  }
  return out;
}

std::vector<SweepCase> far_away(std::mt19937_64& rng, bool quick) {
  std::vector<SweepCase> out;
  for (const double far : {1e4, 1e5, 1e6}) plate_sweeps(rng, far * Vec(1.0, -0.7, 0.4), false, 1, quick ? 2 : 6, out);
  return out;
}

using Generator = std::vector<SweepCase> (*)(std::mt19937_64&, bool);
const std::vector<std::pair<std::string, Generator>>& generators() {
  static const std::vector<std::pair<std::string, Generator>> g = {
      {"toi-thin-plate", thin_plate},           {"toi-grazing", grazing},         {"toi-rotating-bar", rotating_bar},
      {"toi-initial-contact", initial_contact}, {"toi-small-large", small_large}, {"toi-far", far_away}};
  return g;
}

// ---- answers, timed ----------------------------------------------------------

struct Answer {
  bool supported = false, ok = false, hit = false;
  double fraction = 1.0, ns = 0.0;
  std::string status;
};

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// Nanoseconds per call: calls repeated until a loop lasts 20 us, the median of `loops` loops.
double time_per_call(const std::function<double()>& call, int loops) {
  using clock = std::chrono::steady_clock;
  volatile double sink = 0.0;
  const auto loop = [&](int reps) {
    const auto t0 = clock::now();
    for (int i = 0; i < reps; ++i) sink = sink + call();
    return std::chrono::duration<double, std::nano>(clock::now() - t0).count();
  };
  int reps = 1;
  while (reps < (1 << 16) && loop(reps) < 2e4) reps *= 2;
  std::vector<double> per_call;
  for (int l = 0; l < loops; ++l) per_call.push_back(loop(reps) / reps);
  return median(per_call);
}

Answer hedra_answer(const SweepCase& c, bool cast, int loops) {
  Answer a;
  if (cast && c.rotates()) {
    a.status = "unsupported: shape_cast translates only";
    return a;
  }
  const collision::Sweep sa = sweep_of(c.ma), sb = sweep_of(c.mb);
  const Vec ta = c.ma.p1 - c.ma.p0, tb = c.mb.p1 - c.mb.p0;
  const auto query = [&] {
    return cast ? collision::shape_cast(c.a, sa.start, ta, c.b, sb.start, tb)
                : collision::time_of_impact(c.a, sa, c.b, sb);
  };
  const collision::CastResult r = query();
  a.supported = true;
  a.ok = r.status == collision::CastStatus::hit || r.status == collision::CastStatus::separated ||
         r.status == collision::CastStatus::initially_overlapping;
  a.hit = r.hit || r.status == collision::CastStatus::initially_overlapping;
  a.fraction = a.hit ? r.fraction : 1.0;
  a.status = collision::to_string(r.status);
  if (a.ok) a.ns = time_per_call([&] { return query().fraction; }, loops);
  return a;
}

// ---- judging ---------------------------------------------------------------

// The shared rule (first_contact.hpp: judge_contact), at 1e-9 of the size.
reference::ContactVerdict judge(const SweepCase& c, const Answer& a) {
  return reference::judge_contact(c.a, c.ma, c.b, c.mb, c.contact, 0.0, c.size,
                                  reference::contact_tolerance(c.size, c.far), a.hit, a.fraction);
}

// ---- the run ---------------------------------------------------------------

struct MethodRun {
  std::string name;
  std::function<std::vector<Answer>(const std::vector<SweepCase>&)> run;
};

std::vector<MethodRun> methods(const ContinuousOptions& o) {
  std::vector<MethodRun> out;
  for (const bool cast : {false, true})
    out.push_back({cast ? "hedra_shape_cast" : "hedra_toi", [cast, &o](const std::vector<SweepCase>& cases) {
                     std::vector<Answer> answers;
                     for (const SweepCase& c : cases) answers.push_back(hedra_answer(c, cast, o.loops));
                     return answers;
                   }});
#ifdef HEDRA_COMPARE_WITH_PEERS
  for (const peers::ContinuousPeerMethod& m : peers::continuous_peer_methods()) {
    out.push_back({m.name, [&m, &o](const std::vector<SweepCase>& cases) {
                     const auto call = [&](std::size_t i) {
                       const SweepCase& c = cases[i];
                       const peers::SweepPair pair{c.a, sweep_of(c.ma), c.b, sweep_of(c.mb)};
                       const std::unique_ptr<peers::PreparedSweep> prepared = m.prepare(pair);
                       peers::ToiPeerResult r = prepared->query();
                       if (r.supported && r.ok)
                         r.time_ns = time_per_call([&] { return prepared->query().fraction; }, o.loops);
                       return r;
                     };
                     peers::IsolationSettings isolation;
                     isolation.timeout_seconds = o.peer_timeout_seconds;
                     std::vector<Answer> answers;
                     for (const peers::ToiPeerResult& r : peers::run_isolated_toi(call, cases.size(), isolation))
                       answers.push_back({r.supported, r.ok, r.hit, r.hit ? r.fraction : 1.0, r.time_ns, r.status});
                     return answers;
                   }});
  }
#endif
  return out;
}

bool wanted(const std::vector<std::string>& list, const std::string& name) {
  return list.empty() || std::find(list.begin(), list.end(), name) != list.end();
}

ContinuousRow row_of(const std::string& family, const std::string& method, const std::vector<SweepCase>& cases,
                     const std::vector<Answer>& answers) {
  ContinuousRow row{family, method};
  std::vector<double> times;
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const Answer& a = answers[i];
    ++row.cases;
    if (!a.supported) {
      ++row.unsupported;
      continue;
    }
    if (!a.ok) {
      ++row.failures;
      continue;
    }
    ++row.answered;
    times.push_back(a.ns);
    row.hits += a.hit ? 1 : 0;
    const reference::ContactVerdict v = judge(cases[i], a);
    row.tunnelled += v.tunnelled ? 1 : 0;
    row.through += v.through ? 1 : 0;
    row.false_hits += v.false_hit ? 1 : 0;
    row.max_error = std::max(row.max_error, v.error);
  }
  row.median_ns = median(times);
  return row;
}

}  // namespace

const std::vector<std::string>& continuous_family_names() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> n;
    for (const auto& g : generators()) n.push_back(g.first);
    return n;
  }();
  return names;
}

std::vector<std::string> continuous_method_names() {
  std::vector<std::string> names;
  for (const MethodRun& m : methods(ContinuousOptions{})) names.push_back(m.name);
  return names;
}

ContinuousReport run_continuous(const ContinuousOptions& options, std::ostream& progress) {
  ContinuousReport report;
#ifdef HEDRA_COMPARE_WITH_PEERS
  report.peers_built = true;
#endif
  std::vector<double> toi_common, bullet_common;
  std::uint64_t family_seed = options.seed;
  for (const auto& [family, generate] : generators()) {
    std::mt19937_64 rng(family_seed++);  // each family its own stream: --family picks the same sweeps
    if (!wanted(options.families, family)) continue;
    const auto start = std::chrono::steady_clock::now();
    std::vector<SweepCase> cases = generate(rng, options.quick);
    for (SweepCase& c : cases) c.contact = reference::exact_first_contact(c.a, c.ma, c.b, c.mb);
    cases.erase(std::remove_if(cases.begin(), cases.end(), [](const SweepCase& c) { return !c.contact.ok; }),
                cases.end());
    progress << "bench: " << family << ": " << cases.size() << " sweeps, first contacts bracketed in "
             << std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() << " s\n";
    std::map<std::string, std::vector<Answer>> by_method;
    for (const MethodRun& m : methods(options)) {
      if (m.name != "hedra_toi" && !wanted(options.methods, m.name)) continue;
      by_method[m.name] = m.run(cases);
      report.rows.push_back(row_of(family, m.name, cases, by_method[m.name]));
    }
    const auto bullet = by_method.find("bullet_f64_continuous");
    if (bullet == by_method.end()) continue;
    std::vector<double> toi_family, bullet_family;
    for (std::size_t i = 0; i < cases.size(); ++i) {
      const Answer &h = by_method["hedra_toi"][i], &b = bullet->second[i];
      if (h.ok && b.ok && b.supported) {
        toi_family.push_back(h.ns);
        bullet_family.push_back(b.ns);
      }
    }
    if (!toi_family.empty() && median(bullet_family) > 0.0)
      report.family_ratios.emplace_back(family, median(toi_family) / median(bullet_family));
    toi_common.insert(toi_common.end(), toi_family.begin(), toi_family.end());
    bullet_common.insert(bullet_common.end(), bullet_family.begin(), bullet_family.end());
  }
  report.common_sweeps = static_cast<int>(toi_common.size());
  if (!toi_common.empty() && median(bullet_common) > 0.0)
    report.toi_over_bullet = median(toi_common) / median(bullet_common);
  return report;
}

std::string continuous_csv(const ContinuousReport& report) {
  std::ostringstream out;
  out << "family,method,sweeps,answered,unsupported,failures,hits,tunnelled,through,false_hits,median_ns,max_error\n";
  for (const ContinuousRow& r : report.rows)
    out << r.family << "," << r.method << "," << r.cases << "," << r.answered << "," << r.unsupported << ","
        << r.failures << "," << r.hits << "," << r.tunnelled << "," << r.through << "," << r.false_hits << ","
        << r.median_ns << "," << r.max_error << "\n";
  return out.str();
}

std::string continuous_markdown(const ContinuousReport& report, const std::string& header) {
  std::ostringstream out;
  out << header;
  out << "| family | method | sweeps | answered | hits | median ns | tunnelled | of which through | false hits | max "
         "error / size | failures | unsupported |\n|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  char line[400];
  for (const ContinuousRow& r : report.rows) {
    std::snprintf(line, sizeof(line), "| %s | %s | %d | %d | %d | %.0f | %d | %d | %d | %.1e | %d | %d |\n",
                  r.family.c_str(), r.method.c_str(), r.cases, r.answered, r.hits, r.median_ns, r.tunnelled, r.through,
                  r.false_hits, r.max_error, r.failures, r.unsupported);
    out << line;
  }
  if (report.common_sweeps > 0) {
    std::snprintf(line, sizeof(line),
                  "\nhedra_toi / bullet_f64_continuous, median time on the %d sweeps both answered: %.2f\n",
                  report.common_sweeps, report.toi_over_bullet);
    out << line;
    for (const auto& [family, ratio] : report.family_ratios) {
      std::snprintf(line, sizeof(line), "- %s: %.2f\n", family.c_str(), ratio);
      out << line;
    }
  } else if (!report.peers_built) {
    out << "\npeers not built (HEDRA_WITH_PEERS=OFF): hedra only\n";
  }
  return out.str();
}

int continuous_hedra_problems(const ContinuousReport& report) {
  int n = 0;
  for (const ContinuousRow& r : report.rows)
    if (r.method.rfind("hedra", 0) == 0) n += r.tunnelled + r.false_hits + r.failures;
  return n;
}

}  // namespace hedra::tool::bench
