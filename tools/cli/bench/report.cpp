// `hedra bench`'s CSV files and markdown report (see report.hpp).
#include "cli/bench/report.hpp"

#include <sys/utsname.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <optional>
#include <sstream>
#include <thread>

#include "scene/timing.hpp"

namespace hedra::tool::bench {

namespace {

std::string fmt(const char* format, double x) {
  char text[48];
  std::snprintf(text, sizeof text, format, x);
  return text;
}
std::string g6(double x) { return fmt("%.6g", x); }
std::string e3(double x) { return fmt("%.2e", x); }
std::string full(double x) { return fmt("%.17g", x); }
std::string opt(const std::optional<double>& x, std::string (*f)(double)) { return x ? f(*x) : std::string(); }

// A CSV field, quoted when it holds a comma, a quote or a line break.
std::string csv(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string out = "\"";
  for (const char c : s) out += c == '"' ? std::string("\"\"") : std::string(1, c);
  return out + "\"";
}

std::string join(const std::vector<std::string>& items, const std::string& separator) {
  std::string out;
  for (const std::string& item : items) out += (out.empty() ? "" : separator) + item;
  return out;
}

std::string count_text(std::size_t n) { return std::to_string(n); }

// Time for a table cell: ns below 10 us, else us or ms.
std::string time_cell(double ns) { return ns > 0 ? format_time(ns) : "-"; }

// What the run asked, for the report's opening.
std::string question_text(QueryType query) {
  switch (query) {
    case QueryType::distance:
      return "`distance()` against the peers' distance query, on each family's pairs separated by more than the "
             "tolerance (the others are not asked; families without such pairs are left out). Errors are against "
             "the exact distance (the Minkowski-difference hull, qhull): |answer - reference| for polytopes, the "
             "distance from the answer to the reference's certified bracket for curved pairs; relative = absolute / "
             "the pair's size. A failure is an overlap verdict on these separated pairs, an error above the "
             "tolerance (the reference's bound + max(fail tolerance, 2 x requested tolerance) x size), a normal off "
             "a unique reference normal by more than 1e-3 rad (judged where 2 x requested <= fail tolerance), a NaN, "
             "a crash or timeout, or a cap.";
    case QueryType::intersect:
      return "`intersect()` against the peers' boolean query (libccd's ccdGJKIntersect is `ccd_gjk`) on every "
             "pair. Only the verdict is judged, against the sign of the exact signed distance sd: a failure is a "
             "verdict other than sd < 0 where |sd| exceeds the tolerance (the reference's bound + fail tolerance x "
             "size), a crash or timeout, or a cap (for hedra also a stall: its verdict is defined only when ok). "
             "Touching pairs, |sd| within the tolerance, accept either verdict. No errors are measured: the error "
             "columns show `-`.";
    default:
      return "Errors are against the exact reference (the Minkowski-difference hull, qhull): |answer - reference| "
             "for polytopes, the distance from the answer to the reference's certified bracket for curved pairs; "
             "relative = absolute / the pair's size. Times are per query: the median over timed loops per case, then "
             "the median (p99) over the family's cases. A failure is a wrong intersecting verdict, an error above the "
             "tolerance (the reference's bound + max(fail tolerance, 2 x requested tolerance) x size), a normal off a "
             "unique reference normal by more than 1e-3 rad (judged where 2 x requested <= fail tolerance), a NaN, a "
             "crash or timeout, or a cap.";
  }
}

// The fastest peer accurate on the family: poses every case, at most 10 %
// failures, and (except under intersect) a signed distance wherever it
// answers: no boolean-only (partial) answer. A case it could not answer at
// all is one of its failures.
struct FastestPeer {
  std::string name;
  double median_ns = 0.0;
};
std::optional<FastestPeer> fastest_accurate_peer(const BenchReport& report, const FamilyRun& family) {
  std::optional<FastestPeer> best;
  for (std::size_t m = 0; m < report.methods.size() && m < family.results.size(); ++m) {
    if (report.methods[m].is_hedra) continue;
    const Summary s = summarize(family.results[m]);
    const bool distances = report.query == QueryType::intersect || s.partial == 0;
    if (s.cases == 0 || s.supported < s.cases || !distances || 10 * s.failures > s.cases || !(s.time_median_ns > 0))
      continue;
    if (!best || s.time_median_ns < best->median_ns) best = FastestPeer{report.methods[m].name, s.time_median_ns};
  }
  return best;
}

}  // namespace

std::string machine_description() {
  std::string cpu = "unknown CPU";
  std::ifstream info("/proc/cpuinfo");
  for (std::string line; std::getline(info, line);) {
    if (line.rfind("model name", 0) == 0) {
      const std::size_t colon = line.find(':');
      if (colon != std::string::npos) cpu = line.substr(colon + 2);
      break;
    }
  }
  utsname names{};
  std::string system = "unknown system";
  if (uname(&names) == 0) system = std::string(names.sysname) + " " + names.release + " " + names.machine;
  return cpu + ", " + std::to_string(std::thread::hardware_concurrency()) + " cores, " + system;
}

std::string utc_now() {
  const std::time_t now = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&now, &tm);
  char text[32];
  std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return text;
}

std::string load_average() {
  std::ifstream in("/proc/loadavg");
  double a = 0, b = 0, c = 0;
  if (!(in >> a >> b >> c)) return "unknown";
  return fmt("%.2f", a) + " " + fmt("%.2f", b) + " " + fmt("%.2f", c);
}

std::string summary_csv(const BenchReport& report) {
  std::string out =
      "family,method,tolerance,cases,supported,answered,partial,failures,time_median_ns,time_p99_ns,"
      "abs_error_median,abs_error_p99,abs_error_max,rel_error_median,rel_error_p99,rel_error_max,"
      "normal_angle_median,failure_kinds,unsupported\n";
  for (const FamilyRun& family : report.families) {
    for (std::size_t m = 0; m < report.methods.size() && m < family.results.size(); ++m) {
      const Method& method = report.methods[m];
      const Summary s = summarize(family.results[m]);
      const bool errors = s.answered > 0;
      out += csv(family.name) + "," + csv(method.name) + "," + (method.is_hedra ? e3(method.tolerance) : "") + "," +
             count_text(s.cases) + "," + count_text(s.supported) + "," + count_text(s.answered) + "," +
             count_text(s.partial) + "," + count_text(s.failures) + "," +
             (s.time_median_ns > 0 ? g6(s.time_median_ns) : "") + "," + (s.time_p99_ns > 0 ? g6(s.time_p99_ns) : "") +
             "," + (errors ? e3(s.abs_median) : "") + "," + (errors ? e3(s.abs_p99) : "") + "," +
             (errors ? e3(s.abs_max) : "") + "," + (errors ? e3(s.rel_median) : "") + "," +
             (errors ? e3(s.rel_p99) : "") + "," + (errors ? e3(s.rel_max) : "") + "," + opt(s.angle_median, e3) + "," +
             csv(join(s.failure_kinds, "; ")) + "," + csv(join(s.unsupported, "; ")) + "\n";
    }
  }
  return out;
}

std::string cases_csv(const BenchReport& report) {
  std::string out =
      "family,case,label,parameter,method,supported,status,verdict,failure,intersecting,distance,reference,"
      "reference_error_bound,pair_size,tolerance,abs_error,rel_error,normal_angle,time_ns\n";
  for (const FamilyRun& family : report.families) {
    for (std::size_t m = 0; m < report.methods.size() && m < family.results.size(); ++m) {
      for (std::size_t k = 0; k < family.cases.size() && k < family.results[m].size(); ++k) {
        const BenchCase& c = family.cases[k];
        const CaseResult& r = family.results[m][k];
        out += csv(family.name) + "," + std::to_string(k) + "," + csv(c.label) + "," +
               (std::isfinite(c.parameter) ? g6(c.parameter) : "") + "," + csv(report.methods[m].name) + "," +
               (r.answer.supported ? "1" : "0") + "," + csv(r.answer.status) + "," + to_string(r.judgement.verdict) +
               "," + csv(r.failure_kind) + "," + (r.answer.intersecting ? "1" : "0") + "," +
               opt(r.answer.distance, full) + "," + full(c.reference.exact.distance) + "," +
               e3(c.reference.exact.error_bound) + "," + g6(c.reference.pair_size) + "," + e3(r.tolerance) + "," +
               opt(r.abs_error, e3) + "," + opt(r.rel_error, e3) + "," + opt(r.judgement.normal_angle, e3) + "," +
               (r.answer.time_ns > 0 ? g6(r.answer.time_ns) : "") + "\n";
      }
    }
  }
  return out;
}

std::string stability_csv(const BenchReport& report) {
  std::string out = "family,parameter_name,parameter,method,cases,failures,rel_error_median,rel_error_max\n";
  for (const FamilyRun& family : report.families) {
    if (family.parameter.empty()) continue;
    for (std::size_t m = 0; m < report.methods.size() && m < family.results.size(); ++m) {
      for (const StabilityRow& row : stability(family, family.results[m])) {
        out += csv(family.name) + "," + csv(family.parameter) + "," + g6(row.parameter) + "," +
               csv(report.methods[m].name) + "," + count_text(row.cases) + "," + count_text(row.failures) + "," +
               (row.cases ? e3(row.rel_median) : "") + "," + (row.cases ? e3(row.rel_max) : "") + "\n";
      }
    }
  }
  return out;
}

std::string markdown_report(const BenchReport& report, const RunInfo& info) {
  std::ostringstream md;
  md << "# hedra bench"
     << (report.query == QueryType::penetration ? "" : std::string(" --query ") + to_string(report.query)) << "\n\n";
  md << "- date: " << info.date << "\n- machine: " << info.machine << "\n- command: `" << info.command << "`\n";
  md << "- workload: " << info.source << (info.quick ? " (quick)" : "") << ", seed " << info.seed << "\n";
  md << "- load average before / after: " << info.load_before << " / " << info.load_after << "\n";
  double reference_seconds = 0.0;
  for (const FamilyRun& family : report.families) reference_seconds += family.reference_seconds;
  md << "- run time: " << fmt("%.1f", reference_seconds + report.elapsed_seconds) << " s: exact references "
     << fmt("%.1f", reference_seconds) << " s, then timing and judging " << fmt("%.1f", report.elapsed_seconds)
     << " s\n";
  md << "- peers: " << (report.peers_built ? "built" : "not built (HEDRA_WITH_PEERS=OFF): hedra only") << "\n";
  md << "- query: " << to_string(report.query) << "\n\n";
  md << question_text(report.query) << "\n\n";
  if (report.query != QueryType::penetration) {
    md << "Times are per query: the median over timed loops per case, then the median (p99) over the family's "
          "cases.\n\n";
  }

  // Headline: hedra's default beside every peer, per family.
  std::size_t hedra_index = 0;
  for (std::size_t m = 0; m < report.methods.size(); ++m)
    if (report.methods[m].is_default) hedra_index = m;
  md << "## Headline\n\nPer family: hedra's median time, max relative error and failures; for each other "
        "method, its median time as a ratio to hedra's, its max relative error, and failures (`-`: nothing "
        "answered with a distance).\n\n";
  md << "| family | hedra |";
  for (std::size_t m = 0; m < report.methods.size(); ++m)
    if (!report.methods[m].is_hedra) md << " " << report.methods[m].name << " |";
  md << "\n|---|---|";
  for (const Method& method : report.methods)
    if (!method.is_hedra) md << "---|";
  md << "\n";
  for (const FamilyRun& family : report.families) {
    if (family.results.size() <= hedra_index) continue;
    const Summary h = summarize(family.results[hedra_index]);
    md << "| " << family.name << " | " << time_cell(h.time_median_ns) << ", "
       << (h.answered ? e3(h.rel_max) : std::string("-")) << ", " << h.failures << " |";
    for (std::size_t m = 0; m < report.methods.size() && m < family.results.size(); ++m) {
      if (report.methods[m].is_hedra) continue;
      const Summary s = summarize(family.results[m]);
      if (s.supported == 0) {
        md << " unsupported |";
        continue;
      }
      const std::string ratio = h.time_median_ns > 0 && s.time_median_ns > 0
                                    ? fmt("%.2fx", s.time_median_ns / h.time_median_ns)
                                    : std::string("-");
      md << " " << ratio << ", " << (s.answered ? e3(s.rel_max) : std::string("-")) << ", " << s.failures;
      if (s.supported < s.cases) md << " (" << s.supported << "/" << s.cases << ")";
      md << " |";
    }
    md << "\n";
  }
  md << "\n";

  md << "## Against the fastest accurate peer\n\n"
        "Per family: hedra's median time over that of the fastest peer accurate on the family (it poses every "
        "case, has at most 10 % failures"
     << (report.query == QueryType::intersect
             ? ""
             : " and never answers with the verdict alone; a case it could not answer is a failure")
     << ").\n\n";
  const bool against_ccd_gjk =
      report.query == QueryType::intersect &&
      std::any_of(report.methods.begin(), report.methods.end(), [](const Method& m) { return m.name == "ccd_gjk"; });
  md << "| family | hedra | fastest accurate peer | its time | hedra / peer |"
     << (against_ccd_gjk ? " hedra / ccd_gjk |" : "") << "\n|---|---|---|---|---|" << (against_ccd_gjk ? "---|" : "")
     << "\n";
  for (const FamilyRun& family : report.families) {
    if (family.results.size() <= hedra_index) continue;
    const Summary h = summarize(family.results[hedra_index]);
    const std::optional<FastestPeer> peer = fastest_accurate_peer(report, family);
    md << "| " << family.name << " | " << time_cell(h.time_median_ns) << " | ";
    if (peer && h.time_median_ns > 0) {
      md << peer->name << " | " << time_cell(peer->median_ns) << " | "
         << fmt("%.2f", h.time_median_ns / peer->median_ns) << " |";
    } else {
      md << "none | - | - |";
    }
    if (against_ccd_gjk) {
      std::string cell = "-";
      for (std::size_t m = 0; m < report.methods.size() && m < family.results.size(); ++m) {
        if (report.methods[m].name != "ccd_gjk") continue;
        const Summary s = summarize(family.results[m]);
        if (s.time_median_ns > 0 && h.time_median_ns > 0) cell = fmt("%.2f", h.time_median_ns / s.time_median_ns);
      }
      md << " " << cell << " |";
    }
    md << "\n";
  }
  md << "\n";

  md << "## Families\n\n";
  for (const FamilyRun& family : report.families) {
    const FamilyInfo* fi = find_family(family.name);
    md << "### " << family.name << "\n\n"
       << (fi ? fi->description : "scene queries") << ": " << family.cases.size() << " cases";
    if (family.dropped) md << " (" << family.dropped << " dropped: no reference)";
    if (family.skipped) md << " (" << family.skipped << " more not separated beyond the tolerance: not asked)";
    md << ", references in " << fmt("%.1f", family.reference_seconds) << " s.\n\n";
    md << "| method | answered / cases | failures | median time | p99 time | median rel error | p99 rel error | max "
          "rel error | max abs error | median normal angle |\n|---|---|---|---|---|---|---|---|---|---|\n";
    for (std::size_t m = 0; m < report.methods.size() && m < family.results.size(); ++m) {
      const Summary s = summarize(family.results[m]);
      md << "| " << report.methods[m].name << " | " << s.answered << " / " << s.cases;
      if (s.partial) md << " (" << s.partial << " boolean only)";
      md << " | " << s.failures;
      if (!s.failure_kinds.empty()) md << " (" << join(s.failure_kinds, ", ") << ")";
      md << " | " << time_cell(s.time_median_ns) << " | " << time_cell(s.time_p99_ns) << " | ";
      if (s.answered) {
        md << e3(s.rel_median) << " | " << e3(s.rel_p99) << " | " << e3(s.rel_max) << " | " << e3(s.abs_max);
      } else {
        md << "- | - | - | -";
      }
      md << " | " << (s.angle_median ? e3(*s.angle_median) : std::string("-")) << " |\n";
    }
    md << "\n";
  }

  bool any_stability = false;
  for (const FamilyRun& family : report.families) any_stability = any_stability || !family.parameter.empty();
  if (any_stability) {
    md << "## Stability\n\nMax relative error per value of each extreme family's parameter (failures in "
          "brackets).\n\n";
    for (const FamilyRun& family : report.families) {
      if (family.parameter.empty() || family.results.empty()) continue;
      const std::vector<StabilityRow> first = stability(family, family.results[0]);
      md << "### " << family.name << " (" << family.parameter << ")\n\n| method |";
      for (const StabilityRow& row : first) md << " " << g6(row.parameter) << " |";
      md << "\n|---|";
      for (std::size_t k = 0; k < first.size(); ++k) md << "---|";
      md << "\n";
      for (std::size_t m = 0; m < report.methods.size() && m < family.results.size(); ++m) {
        md << "| " << report.methods[m].name << " |";
        for (const StabilityRow& row : stability(family, family.results[m])) {
          md << " " << (row.cases ? e3(row.rel_max) : std::string("-"));
          if (row.failures) md << " (" << row.failures << ")";
          md << " |";
        }
        md << "\n";
      }
      md << "\n";
    }
  }

  md << "## What each method could not pose\n\n";
  bool any_unsupported = false;
  for (std::size_t m = 0; m < report.methods.size(); ++m) {
    for (const FamilyRun& family : report.families) {
      if (m >= family.results.size()) continue;
      const Summary s = summarize(family.results[m]);
      if (s.unsupported.empty() && s.partial == 0) continue;
      any_unsupported = true;
      md << "- " << report.methods[m].name << ", " << family.name << ": ";
      if (!s.unsupported.empty()) md << "unsupported " << join(s.unsupported, "; ");
      if (s.partial) md << (s.unsupported.empty() ? "" : "; ") << s.partial << " answered the boolean only";
      md << "\n";
    }
  }
  if (!any_unsupported) md << "Every method posed every case.\n";
  md << "\n";

  std::size_t dropped = 0;
  for (const FamilyRun& family : report.families) dropped += family.dropped;
  if (dropped) {
    md << "## Dropped cases\n\n";
    for (const FamilyRun& family : report.families)
      for (const std::string& note : family.notes) md << "- " << note << "\n";
    md << "\n";
  }
  return md.str();
}

}  // namespace hedra::tool::bench
