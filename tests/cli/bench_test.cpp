// `hedra bench`: the workloads (signs and sweeps as advertised,
// reproducible from the seed), the judging rules on fabricated answers, the
// summaries, and the subcommand end to end: the quick run (every output file
// well formed, hedra without failures, figures made where matplotlib is)
// and bad input (exit 2, nothing on stdout, nothing written).
#include "cli/bench/bench.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <set>
#include <sstream>

#include "cli/bench/workloads.hpp"
#include "cli_fixture.hpp"

namespace {

using namespace hedra::tool;
using namespace hedra::tool::bench;
using hedra::cli_test::HedraCli;
using hedra::cli_test::RunResult;
using hedra::cli_test::slurp;
namespace fs = std::filesystem;

// ---- workloads ------------------------------------------------------------------

WorkloadOptions quick(std::uint64_t seed = 1) {
  WorkloadOptions o;
  o.seed = seed;
  o.quick = true;
  return o;
}

TEST(BenchWorkloads, EveryFamilyHasCasesWithExactReferences) {
  for (const FamilyInfo& info : families()) {
    const FamilyCases made = make_family(info.name, quick());
    EXPECT_GE(made.cases.size(), 4u) << info.name;
    EXPECT_EQ(made.dropped, 0u) << info.name << ": " << (made.notes.empty() ? "" : made.notes.front());
    for (const BenchCase& c : made.cases) {
      EXPECT_TRUE(c.reference.exact.ok) << info.name << " " << c.label;
      EXPECT_TRUE(std::isfinite(c.reference.exact.distance)) << info.name << " " << c.label;
      EXPECT_GT(c.reference.pair_size, 0.0) << info.name;
      EXPECT_EQ(c.family, info.name);
      EXPECT_EQ(std::string(info.parameter).empty(), !std::isfinite(c.parameter)) << info.name << " " << c.label;
    }
  }
}

TEST(BenchWorkloads, SignsAreWhatTheFamiliesSay) {
  for (const BenchCase& c : make_family("poly-separated", quick()).cases) EXPECT_GT(c.reference.exact.distance, 0.0);
  for (const BenchCase& c : make_family("poly-penetrating", quick()).cases) EXPECT_LT(c.reference.exact.distance, 0.0);
  for (const BenchCase& c : make_family("touching", quick()).cases) {
    EXPECT_LE(std::abs(c.reference.exact.distance), 1e-12 * c.reference.pair_size + c.reference.exact.error_bound)
        << c.label;
  }
  int coincident = 0;
  for (const BenchCase& c : make_family("deep", quick()).cases) {
    EXPECT_LT(c.reference.exact.distance, -0.05 * c.reference.pair_size) << c.label;
    coincident += c.parameter == 0.0 ? 1 : 0;
  }
  EXPECT_GE(coincident, 1);
  // Both outcomes occur where a family mixes them.
  for (const char* family : {"parallel", "thin", "scale", "rounded", "curved"}) {
    int apart = 0, overlapping = 0;
    for (const BenchCase& c : make_family(family, quick()).cases)
      (c.reference.exact.distance > 0 ? apart : overlapping)++;
    EXPECT_GT(apart, 0) << family;
    EXPECT_GT(overlapping, 0) << family;
  }
}

TEST(BenchWorkloads, ExtremeFamiliesSweepTheirParameterOverDecades) {
  std::set<double> angles, ratios, offsets;
  for (const BenchCase& c : make_family("parallel", quick()).cases) angles.insert(c.parameter);
  for (const BenchCase& c : make_family("scale", quick()).cases) ratios.insert(c.parameter);
  for (const BenchCase& c : make_family("far", quick()).cases) offsets.insert(c.parameter);
  EXPECT_EQ(angles, (std::set<double>{1e-9, 1e-8, 1e-7, 1e-6, 1e-5, 1e-4}));
  EXPECT_EQ(*ratios.begin(), 1.0);
  EXPECT_EQ(*ratios.rbegin(), 1e6);
  EXPECT_EQ(*offsets.rbegin(), 1e6);
  for (const BenchCase& c : make_family("far", quick()).cases)
    EXPECT_NEAR(c.pose_a.translation.norm(), c.parameter, 1e-9 * c.parameter) << c.label;
}

// Regression: the kind of pair was once tied to the parameter (every offset
// of `far` all apart or all deep). Each parameter value must meet both.
TEST(BenchWorkloads, EveryParameterValueMeetsBothOutcomes) {
  WorkloadOptions full;
  for (const char* family : {"far", "scale", "parallel", "thin"}) {
    std::map<double, std::set<bool>> outcomes;
    for (const BenchCase& c : make_family(family, full).cases)
      outcomes[c.parameter].insert(c.reference.exact.distance < 0);
    for (const auto& [parameter, seen] : outcomes) EXPECT_EQ(seen.size(), 2u) << family << " at " << parameter;
  }
}

TEST(BenchWorkloads, TheSeedDecidesTheCases) {
  const FamilyCases a = make_family("poly-penetrating", quick(7)), b = make_family("poly-penetrating", quick(7));
  const FamilyCases c = make_family("poly-penetrating", quick(8));
  ASSERT_EQ(a.cases.size(), b.cases.size());
  for (std::size_t k = 0; k < a.cases.size(); ++k)
    EXPECT_EQ(a.cases[k].reference.exact.distance, b.cases[k].reference.exact.distance);
  EXPECT_NE(a.cases[0].reference.exact.distance, c.cases[0].reference.exact.distance);
}

// ---- judging ----------------------------------------------------------------------

struct Judging : ::testing::Test {
  void SetUp() override {
    c = make_family("poly-penetrating", quick()).cases.at(0);
    for (const Method& m : all_methods(true)) {
      if (m.is_default) hedra = m;
      if (m.name == "hedra@1e-03") loose = m;
    }
    peer.name = "peer";
  }
  // The reference's own answer, as a method would give it.
  MethodAnswer exact_answer() const {
    MethodAnswer a;
    a.method = "x";
    a.intersecting = c.reference.exact.distance < 0;
    a.distance = c.reference.exact.distance;
    a.normal = c.reference.exact.normal;
    a.time_ns = 100;
    return a;
  }
  BenchCase c;
  Method hedra, loose, peer;
};

TEST_F(Judging, TheExactAnswerPasses) {
  const CaseResult r = judge_case(c, hedra, exact_answer(), 1e-6);
  EXPECT_FALSE(r.failure) << r.judgement.detail;
  ASSERT_TRUE(r.abs_error.has_value());
  EXPECT_EQ(*r.abs_error, 0.0);
  EXPECT_NEAR(r.tolerance, c.reference.exact.error_bound + 1e-6 * c.reference.pair_size, 1e-18);
}

TEST_F(Judging, AnErrorAboveTheToleranceFails) {
  MethodAnswer a = exact_answer();
  *a.distance += 3e-6 * c.reference.pair_size;
  const CaseResult r = judge_case(c, peer, a, 1e-6);
  EXPECT_TRUE(r.failure);
  EXPECT_EQ(r.failure_kind, "error");
  EXPECT_NEAR(*r.rel_error, 3e-6, 1e-12);
  // The same error is within what hedra@1e-3 asked for.
  EXPECT_FALSE(judge_case(c, loose, a, 1e-6).failure);
}

TEST_F(Judging, AWrongVerdictIsAClassificationFailure) {
  MethodAnswer a = exact_answer();
  a.intersecting = !a.intersecting;
  const CaseResult r = judge_case(c, peer, a, 1e-6);
  EXPECT_TRUE(r.failure);
  EXPECT_EQ(r.failure_kind, "classification");
}

TEST_F(Judging, NormalsAreJudgedOnlyWhereTheToleranceAsksForThem) {
  ASSERT_TRUE(c.reference.exact.normal_unique);
  MethodAnswer a = exact_answer();
  const Eigen::Vector3d n = c.reference.exact.normal;
  const Eigen::Vector3d side = n.unitOrthogonal();
  a.normal = (n * std::cos(0.1) + side * std::sin(0.1)).normalized();
  const CaseResult r = judge_case(c, peer, a, 1e-6);
  EXPECT_TRUE(r.failure);
  EXPECT_EQ(r.failure_kind, "normal");
  EXPECT_NEAR(*r.judgement.normal_angle, 0.1, 1e-9);
  EXPECT_FALSE(judge_case(c, loose, a, 1e-6).failure);
}

TEST_F(Judging, FailedUnsupportedAndNanAnswers) {
  MethodAnswer crashed;
  crashed.ok = false;
  crashed.status = "crashed (signal 11)";
  const CaseResult r = judge_case(c, peer, crashed, 1e-6);
  EXPECT_TRUE(r.failure);
  EXPECT_EQ(r.failure_kind, "failed: crashed (signal 11)");

  MethodAnswer unsupported;
  unsupported.supported = false;
  unsupported.status = "no margins";
  const CaseResult u = judge_case(c, peer, unsupported, 1e-6);
  EXPECT_FALSE(u.failure);

  MethodAnswer nan = exact_answer();
  nan.distance = std::nan("");
  EXPECT_TRUE(judge_case(c, peer, nan, 1e-6).failure);

  const Summary s = summarize({r, u, judge_case(c, peer, exact_answer(), 1e-6)});
  EXPECT_EQ(s.cases, 3u);
  EXPECT_EQ(s.supported, 2u);
  EXPECT_EQ(s.answered, 1u);
  EXPECT_EQ(s.failures, 1u);
  EXPECT_EQ(s.unsupported, std::vector<std::string>{"no margins x1"});
  EXPECT_EQ(s.failure_kinds, std::vector<std::string>{"failed: crashed (signal 11) x1"});
}

// --query intersect judges the verdict alone: the reference's sign beyond
// the tolerance, either verdict on a touching pair.
TEST_F(Judging, IntersectJudgesTheVerdictAlone) {
  ASSERT_LT(c.reference.exact.distance, -1e-3 * c.reference.pair_size);
  MethodAnswer a;
  a.method = "x";
  a.intersecting = true;
  const CaseResult right = judge_case(c, hedra, a, 1e-6, QueryType::intersect);
  EXPECT_FALSE(right.failure) << right.judgement.detail;
  EXPECT_EQ(right.judgement.verdict, Verdict::agree);
  EXPECT_FALSE(right.abs_error.has_value());
  a.intersecting = false;
  const CaseResult wrong = judge_case(c, hedra, a, 1e-6, QueryType::intersect);
  EXPECT_TRUE(wrong.failure);
  EXPECT_EQ(wrong.failure_kind, "classification");
  // A distance, however wrong, is not what intersect asks.
  a.intersecting = true;
  a.distance = 1e3;
  EXPECT_FALSE(judge_case(c, peer, a, 1e-6, QueryType::intersect).failure);

  for (const BenchCase& t : make_family("touching", quick()).cases) {
    for (const bool verdict : {true, false}) {
      MethodAnswer b;
      b.intersecting = verdict;
      EXPECT_FALSE(judge_case(t, peer, b, 1e-6, QueryType::intersect).failure) << t.label << " " << verdict;
    }
  }
}

// --query distance asks only pairs separated beyond the tolerance, and
// judges them as penetration does.
TEST_F(Judging, DistanceIsAskedOnSeparatedPairsOnly) {
  EXPECT_FALSE(asks_about(QueryType::distance, c, 1e-6));
  EXPECT_TRUE(asks_about(QueryType::intersect, c, 1e-6));
  EXPECT_TRUE(asks_about(QueryType::penetration, c, 1e-6));
  for (const BenchCase& t : make_family("touching", quick()).cases)
    EXPECT_FALSE(asks_about(QueryType::distance, t, 1e-6));
  const BenchCase apart = make_family("poly-separated", quick()).cases.at(0);
  ASSERT_TRUE(asks_about(QueryType::distance, apart, 1e-6));
  MethodAnswer a;
  a.distance = apart.reference.exact.distance;
  a.normal = apart.reference.exact.normal;
  EXPECT_FALSE(judge_case(apart, hedra, a, 1e-6, QueryType::distance).failure);
  a.intersecting = true;  // an overlap verdict on a separated pair
  EXPECT_EQ(judge_case(apart, hedra, a, 1e-6, QueryType::distance).failure_kind, "classification");
  a.intersecting = false;
  *a.distance += 3e-6 * apart.reference.pair_size;
  EXPECT_EQ(judge_case(apart, peer, a, 1e-6, QueryType::distance).failure_kind, "error");

  FamilyRun family;
  family.cases = {c, apart};
  BenchOptions options;
  options.query = QueryType::distance;
  keep_asked_cases(family, options);
  ASSERT_EQ(family.cases.size(), 1u);
  EXPECT_EQ(family.cases[0].label, apart.label);
  EXPECT_EQ(family.skipped, 1u);
}

TEST(BenchQueries, MethodsPerQuery) {
  const auto names = [](QueryType q) {
    std::set<std::string> out;
    for (const Method& m : all_methods(true, q)) out.insert(m.name);
    return out;
  };
  EXPECT_EQ(names(QueryType::penetration), names(QueryType::distance));
  EXPECT_EQ(names(QueryType::penetration).count("ccd_gjk"), 0u);
  EXPECT_EQ(names(QueryType::intersect).count("hedra@1e-03"), 0u);
  EXPECT_EQ(names(QueryType::intersect).count("hedra"), 1u);
#if defined(HEDRA_COMPARE_WITH_PEERS)
  EXPECT_EQ(names(QueryType::intersect).count("ccd_gjk"), 1u);
#endif
  EXPECT_EQ(find_bench_query("distance"), QueryType::distance);
  EXPECT_EQ(find_bench_query("intersect"), QueryType::intersect);
  EXPECT_EQ(find_bench_query("contact"), std::nullopt);
}

TEST(BenchSummary, MediansAndNearestRankPercentiles) {
  std::vector<CaseResult> results;
  for (int k = 1; k <= 100; ++k) {
    CaseResult r;
    r.answer.time_ns = k;
    r.abs_error = k * 1e-16;
    r.rel_error = k * 1e-17;
    r.judgement.verdict = Verdict::agree;
    results.push_back(r);
  }
  const Summary s = summarize(results);
  EXPECT_EQ(s.time_median_ns, 50.5);
  EXPECT_EQ(s.time_p99_ns, 99.0);
  EXPECT_DOUBLE_EQ(s.abs_max, 100e-16);
  EXPECT_DOUBLE_EQ(s.rel_median, 50.5e-17);
  EXPECT_EQ(s.answered, 100u);

  FamilyRun family;
  for (int k = 0; k < 100; ++k) {
    BenchCase c;
    c.parameter = k % 2 ? 1e-3 : 1e-6;
    family.cases.push_back(c);
  }
  const std::vector<StabilityRow> rows = stability(family, results);
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[0].parameter, 1e-6);
  EXPECT_EQ(rows[0].cases, 50u);
  EXPECT_DOUBLE_EQ(rows[0].rel_max, 99e-17);  // the 1e-6 group: even case indices, errors 1, 3, ... 99 e-17
  EXPECT_DOUBLE_EQ(rows[1].rel_max, 100e-17);
}

// ---- the subcommand ----------------------------------------------------------------

// RFC 4180 rows (quoted fields, doubled quotes), header first.
std::vector<std::vector<std::string>> read_csv(const std::string& text) {
  std::vector<std::vector<std::string>> rows(1);
  std::string field;
  bool quoted = false, any = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char ch = text[i];
    any = true;
    if (quoted) {
      if (ch == '"' && i + 1 < text.size() && text[i + 1] == '"') {
        field += '"';
        ++i;
      } else if (ch == '"') {
        quoted = false;
      } else {
        field += ch;
      }
    } else if (ch == '"') {
      quoted = true;
    } else if (ch == ',') {
      rows.back().push_back(field);
      field.clear();
    } else if (ch == '\n') {
      rows.back().push_back(field);
      field.clear();
      rows.emplace_back();
      any = false;
    } else {
      field += ch;
    }
  }
  if (any) rows.back().push_back(field);
  if (rows.back().empty()) rows.pop_back();
  return rows;
}

// Column name -> value, for every data row; each row must have the header's width.
std::vector<std::map<std::string, std::string>> records(const std::string& text, const std::string& header) {
  const auto rows = read_csv(text);
  std::vector<std::map<std::string, std::string>> out;
  EXPECT_FALSE(rows.empty());
  if (rows.empty()) return out;
  std::string first;
  for (const std::string& h : rows[0]) first += (first.empty() ? "" : ",") + h;
  EXPECT_EQ(first, header);
  for (std::size_t r = 1; r < rows.size(); ++r) {
    EXPECT_EQ(rows[r].size(), rows[0].size()) << "row " << r;
    std::map<std::string, std::string> record;
    for (std::size_t k = 0; k < rows[0].size() && k < rows[r].size(); ++k) record[rows[0][k]] = rows[r][k];
    out.push_back(record);
  }
  return out;
}

// An empty cell, or a finite number written in full.
bool number_or_empty(const std::string& cell) {
  if (cell.empty()) return true;
  char* end = nullptr;
  const double x = std::strtod(cell.c_str(), &end);
  return end == cell.c_str() + cell.size() && std::isfinite(x);
}

bool matplotlib_available() { return std::system("/usr/bin/python3 -c 'import matplotlib' >/dev/null 2>&1") == 0; }

using BenchCli = HedraCli;

TEST_F(BenchCli, QuickRunWritesWellFormedOutputsAndHedraHasNoFailure) {
  const fs::path out = dir_ / "bench";
  const RunResult result = run({"bench", "--quick", "--out", out.string()});
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_EQ(result.out.rfind("# hedra bench", 0), 0u);
  EXPECT_EQ(result.out, slurp(out / "report.md"));
  EXPECT_NE(result.err.find("bench: poly-separated"), std::string::npos) << "progress on stderr";
  EXPECT_NE(result.err.find("hedra failures: 0"), std::string::npos) << result.err;

  const std::vector<Method> methods = all_methods(true);
  const auto summary =
      records(slurp(out / "summary.csv"),
              "family,method,tolerance,cases,supported,answered,partial,failures,time_median_ns,time_p99_ns,"
              "abs_error_median,abs_error_p99,abs_error_max,rel_error_median,rel_error_p99,rel_error_max,"
              "normal_angle_median,failure_kinds,unsupported");
  EXPECT_EQ(summary.size(), families().size() * methods.size());
  std::map<std::string, std::size_t> cases_per_family;
  for (const auto& row : summary) {
    for (const char* column : {"cases", "supported", "answered", "failures", "time_median_ns", "time_p99_ns",
                               "abs_error_max", "rel_error_median", "rel_error_max", "normal_angle_median"})
      EXPECT_TRUE(number_or_empty(row.at(column))) << column << " = '" << row.at(column) << "'";
    cases_per_family[row.at("family")] = std::stoul(row.at("cases"));
    if (row.at("method").rfind("hedra", 0) != 0) continue;
    const std::string where = row.at("family") + " " + row.at("method");
    EXPECT_EQ(row.at("failures"), "0") << where << ": " << row.at("failure_kinds");
    EXPECT_EQ(row.at("answered"), row.at("cases")) << where;
    EXPECT_GT(std::stod(row.at("time_median_ns")), 0.0) << where;
    // hedra's default settings hold the contract: within 1e-9 of the size.
    if (row.at("method") == "hedra") {
      EXPECT_LE(std::stod(row.at("rel_error_max")), 1e-9) << where;
    }
  }
  EXPECT_EQ(cases_per_family.size(), families().size());

  const auto cases = records(slurp(out / "cases.csv"),
                             "family,case,label,parameter,method,supported,status,verdict,failure,intersecting,"
                             "distance,reference,reference_error_bound,pair_size,tolerance,abs_error,rel_error,"
                             "normal_angle,time_ns");
  std::size_t expected_rows = 0;
  for (const auto& [family, n] : cases_per_family) expected_rows += n * methods.size();
  EXPECT_EQ(cases.size(), expected_rows);
  for (const auto& row : cases) {
    for (const char* column : {"parameter", "distance", "reference", "abs_error", "rel_error", "time_ns"})
      EXPECT_TRUE(number_or_empty(row.at(column))) << column << " = '" << row.at(column) << "'";
    if (row.at("method").rfind("hedra", 0) == 0) {
      EXPECT_FALSE(row.at("distance").empty()) << row.at("label");
    }
  }

  const auto stability_rows =
      records(slurp(out / "stability.csv"),
              "family,parameter_name,parameter,method,cases,failures,rel_error_median,rel_error_max");
  std::set<std::string> swept;
  std::set<double> angles;
  for (const auto& row : stability_rows) {
    swept.insert(row.at("family"));
    if (row.at("family") == "parallel" && row.at("method") == "hedra") angles.insert(std::stod(row.at("parameter")));
  }
  EXPECT_EQ(swept, (std::set<std::string>{"deep", "parallel", "thin", "scale", "far", "large-hull"}));
  EXPECT_EQ(angles.size(), 6u);

  const std::string md = slurp(out / "report.md");
  for (const FamilyInfo& info : families())
    EXPECT_NE(md.find("| " + std::string(info.name) + " | "), std::string::npos) << info.name;

  if (!matplotlib_available()) {
    EXPECT_NE(result.err.find("plots not made"), std::string::npos);
    GTEST_SKIP() << "matplotlib is not installed: the figures were not checked";
  }
  for (const char* stem : {"error_vs_time", "stability"}) {
    EXPECT_EQ(slurp(out / (std::string(stem) + ".png")).substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8)) << stem;
    EXPECT_NE(slurp(out / (std::string(stem) + ".svg")).find("<svg"), std::string::npos) << stem;
  }
}

TEST_F(BenchCli, QuickContinuousRunNeverTunnels) {
  const fs::path out = dir_ / "continuous";
  const RunResult result = run({"bench", "--continuous", "--quick", "--loops", "1", "--out", out.string()});
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_EQ(result.out.rfind("# hedra bench --continuous", 0), 0u);
  EXPECT_EQ(result.out, slurp(out / "continuous.md"));
  EXPECT_NE(result.err.find("hedra tunnelled, false hits or failures: 0"), std::string::npos) << result.err;
  const auto rows = records(slurp(out / "continuous.csv"),
                            "family,method,sweeps,answered,unsupported,failures,hits,tunnelled,through,false_hits,"
                            "median_ns,max_error");
  std::set<std::string> families_seen;
  for (const auto& row : rows) {
    for (const char* column : {"sweeps", "answered", "tunnelled", "median_ns", "max_error"})
      EXPECT_TRUE(number_or_empty(row.at(column))) << column << " = '" << row.at(column) << "'";
    families_seen.insert(row.at("family"));
    if (row.at("method") != "hedra_toi") continue;
    const std::string where = row.at("family");
    EXPECT_EQ(row.at("answered"), row.at("sweeps")) << where;
    EXPECT_EQ(row.at("tunnelled"), "0") << where;
    EXPECT_EQ(row.at("false_hits"), "0") << where;
    EXPECT_GT(std::stod(row.at("median_ns")), 0.0) << where;
    // Within 1e-9 of the size in distance; along the motion a grazing
    // approach stretches that (5.6e-9 on toi-grazing).
    EXPECT_LE(std::stod(row.at("max_error")), 1e-8) << where;
  }
  EXPECT_EQ(families_seen, (std::set<std::string>{"toi-thin-plate", "toi-grazing", "toi-rotating-bar",
                                                  "toi-initial-contact", "toi-small-large", "toi-far"}));
  const RunResult bad = run({"bench", "--continuous", "--family", "poly-separated", "--out", out.string()});
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.err.find("unknown name 'poly-separated'"), std::string::npos) << bad.err;
}

TEST_F(BenchCli, ASceneIsBenchmarkedQueryByQuery) {
  const fs::path out = dir_ / "scene";
  const RunResult result = run({"bench", "--scene", std::string(HEDRA_SOURCE_DIR) + "/scenes/demo.json", "--method",
                                "hedra", "--no-plots", "--loops", "1", "--out", out.string()});
  ASSERT_EQ(result.exit_code, 0) << result.err;
  const auto summary = read_csv(slurp(out / "summary.csv"));
  ASSERT_EQ(summary.size(), 2u);  // header + hedra
  EXPECT_EQ(summary[1][0].rfind("scene:", 0), 0u);
  EXPECT_EQ(summary[1][1], "hedra");
  EXPECT_FALSE(fs::exists(out / "error_vs_time.png"));
  // The run time covers the whole run, the exact references included, to
  // a tenth of a second, and its parts add up to it.
  const std::string md = slurp(out / "report.md");
  const std::size_t at = md.find("- run time: ");
  ASSERT_NE(at, std::string::npos) << md;
  double total = 0.0, references = 0.0, timing = 0.0;
  ASSERT_EQ(std::sscanf(md.c_str() + at, "- run time: %lf s: exact references %lf s, then timing and judging %lf s",
                        &total, &references, &timing),
            3)
      << md.substr(at, 120);
  EXPECT_GE(references, 0.0);
  EXPECT_NEAR(total, references + timing, 0.11);
  // "0 failures", "1 failure", never "1 failures".
  EXPECT_EQ(result.err.find(" 1 failures"), std::string::npos) << result.err;
  EXPECT_EQ(result.err.find(" 1 cases"), std::string::npos) << result.err;
}

// --query intersect and --query distance end to end: the report, and every
// hedra verdict against the reference's sign as cases.csv records it.
TEST_F(BenchCli, QueryIntersectAndDistanceRuns) {
  const fs::path out = dir_ / "intersect";
  const RunResult result = run({"bench", "--quick", "--query", "intersect", "--family", "poly-separated", "--family",
                                "poly-penetrating", "--family", "touching", "--loops", "1", "--out", out.string()});
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_EQ(result.out.rfind("# hedra bench --query intersect", 0), 0u);
  EXPECT_EQ(result.out, slurp(out / "report.md"));
  EXPECT_NE(result.out.find("## Against the fastest accurate peer"), std::string::npos);
  EXPECT_NE(result.err.find("no plots for --query intersect"), std::string::npos) << result.err;
  const std::string header =
      "family,case,label,parameter,method,supported,status,verdict,failure,intersecting,distance,reference,"
      "reference_error_bound,pair_size,tolerance,abs_error,rel_error,normal_angle,time_ns";
  std::map<std::string, int> hedra_rows;
  std::set<std::string> methods_seen;
  for (const auto& row : records(slurp(out / "cases.csv"), header)) {
    methods_seen.insert(row.at("method"));
    EXPECT_TRUE(row.at("distance").empty()) << "intersect answers no distance";
    if (row.at("method") != "hedra") continue;
    ++hedra_rows[row.at("family")];
    const double sd = std::stod(row.at("reference"));
    const std::string where = row.at("family") + " " + row.at("label");
    EXPECT_EQ(row.at("verdict"), "agree") << where;
    if (row.at("family") == "poly-separated") {
      EXPECT_EQ(row.at("intersecting"), "0") << where;
    }
    if (row.at("family") == "poly-penetrating") {
      EXPECT_EQ(row.at("intersecting"), "1") << where;
    }
    if (std::abs(sd) > std::stod(row.at("tolerance"))) {
      EXPECT_EQ(row.at("intersecting"), sd < 0 ? "1" : "0") << where;
    }
    EXPECT_GT(std::stod(row.at("time_ns")), 0.0) << where;
  }
  EXPECT_EQ(hedra_rows.size(), 3u);
  EXPECT_EQ(methods_seen.count("hedra@1e-03"), 0u);
#if defined(HEDRA_COMPARE_WITH_PEERS)
  EXPECT_EQ(methods_seen.count("ccd_gjk"), 1u);
  EXPECT_NE(result.out.find("hedra / ccd_gjk"), std::string::npos);
#endif

  const fs::path dout = dir_ / "distance";
  const RunResult d = run({"bench", "--quick", "--query", "distance", "--family", "poly-separated", "--family",
                           "poly-penetrating", "--no-plots", "--loops", "1", "--out", dout.string()});
  ASSERT_EQ(d.exit_code, 0) << d.err;
  EXPECT_EQ(d.out.rfind("# hedra bench --query distance", 0), 0u);
  EXPECT_NE(d.err.find("not separated beyond the tolerance: not asked"), std::string::npos) << d.err;
  std::size_t hedra_cases = 0;
  for (const auto& row : records(slurp(dout / "cases.csv"), header)) {
    EXPECT_EQ(row.at("family"), "poly-separated") << "no pair of poly-penetrating is separated";
    EXPECT_GT(std::stod(row.at("reference")), 0.0);
    if (row.at("method") != "hedra") continue;
    ++hedra_cases;
    EXPECT_EQ(row.at("verdict"), "agree") << row.at("label");
    EXPECT_EQ(row.at("intersecting"), "0") << row.at("label");
    EXPECT_LE(std::abs(std::stod(row.at("distance")) - std::stod(row.at("reference"))), std::stod(row.at("tolerance")));
  }
  EXPECT_GT(hedra_cases, 0u);
}

TEST_F(BenchCli, BadInputExitsTwoAndWritesNothing) {
  const fs::path out = dir_ / "never";
  expect_bad({"bench", "--family", "nope", "--out", out.string()}, {"unknown family 'nope'", "poly-separated"});
  expect_bad({"bench", "--method", "nope", "--out", out.string()}, {"unknown method 'nope'", "hedra@1e-03"});
  expect_bad({"bench", "--scene", (work_ / "missing.json").string(), "--out", out.string()}, {"missing.json"});
  const std::string bad_scene = write("bad.json",
                                      "{\"hedra_scene\": 1, \"shapes\": {\"s\": {\"type\": \"sphere\", "
                                      "\"radius\": -1}}, \"bodies\": {}, \"queries\": []}");
  expect_bad({"bench", "--scene", bad_scene, "--out", out.string()}, {"bad.json", "radius"});
  expect_bad({"bench", "--loops", "0", "--out", out.string()}, {"loops"});
  expect_bad({"bench", "--query", "contact", "--out", out.string()},
             {"--query: unknown query 'contact'", "penetration, distance, intersect"});
  expect_bad({"bench", "--continuous", "--query", "distance", "--out", out.string()}, {"--continuous"});
  expect_bad({"bench", "--query", "intersect", "--method", "hedra@1e-03", "--out", out.string()},
             {"unknown method 'hedra@1e-03'", "--query intersect"});
  EXPECT_FALSE(fs::exists(out)) << "bad input must not create the output directory";
  const std::string file = write("a_file", "x");
  expect_bad({"bench", "--quick", "--family", "touching", "--out", file + "/sub"}, {"cannot create"});
}

}  // namespace
