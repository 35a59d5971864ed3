// `hedra bench`: the command line around bench.hpp and report.hpp.
//
// Order of work: check the options (unknown family or method names, an
// unreadable scene: exit 2 before anything runs) -> create the output
// directory and open every output's temporary file (an unwritable directory
// fails before minutes of work) -> generate the cases and their references
// -> time and judge -> commit the CSV files, the report and the plotting
// script (each written whole or not at all) -> run the script with
// /usr/bin/python3 (matplotlib) for the PNG and SVG figures. Progress goes to
// stderr, the markdown report to stdout. Exit 0 when hedra (every tolerance
// of the sweep) has no failure, 1 when it has some, 2 for bad input.
// --continuous runs the sweep families of continuous.hpp instead, through
// the same steps (no plots). --query distance|intersect asks hedra's
// distance() or intersect() and the peers' same question instead of the
// signed distance (bench.hpp); intersect makes no plots (no error to draw).
#include "cli/bench/bench_command.hpp"

#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "cli/atomic_file.hpp"
#include "cli/bench/bench.hpp"
#include "cli/bench/continuous.hpp"
#include "cli/bench/report.hpp"
#include "cli/cli_validators.hpp"
#include "scene/scene_runner.hpp"

extern char** environ;

namespace hedra::tool {

namespace {

namespace fs = std::filesystem;

struct BenchCommandOptions {
  bool quick = false;
  bool continuous = false;
  std::string out = "bench-results";
  std::uint64_t seed = 1;
  std::vector<std::string> families;
  std::vector<std::string> methods;
  std::string scene;
  std::string query = "penetration";
  double fail_tolerance = 1e-6;
  double peer_timeout = 20.0;
  int loops = 0;  // 0: 7, or 3 with --quick
  bool no_plots = false;
  std::string python;
  std::string command_line;
};

// Runs `python script out_dir`, its stdout sent to stderr (stdout is the
// report's). Returns the reason it failed, or "" on success.
std::string run_plots(const std::string& python, const std::string& script, const std::string& out_dir) {
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, STDERR_FILENO, STDOUT_FILENO);
  std::vector<std::string> args = {python, script, out_dir};
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  pid_t pid = 0;
  const int spawned = posix_spawnp(&pid, python.c_str(), &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (spawned != 0) return "cannot run " + python + ": " + std::strerror(spawned);
  int status = 0;
  while (waitpid(pid, &status, 0) < 0) {
    if (errno != EINTR) return "waitpid failed: " + std::string(std::strerror(errno));
  }
  if (WIFEXITED(status) && WEXITSTATUS(status) == 0) return "";
  return python + " " + script + " exited with " +
         (WIFEXITED(status) ? std::to_string(WEXITSTATUS(status)) : "a signal");
}

// The options as a command line that repeats the run (for the report).
std::string command_text(const BenchCommandOptions& o) {
  std::string line = "hedra bench";
  if (o.quick) line += " --quick";
  if (o.continuous) line += " --continuous";
  if (o.query != "penetration") line += " --query " + o.query;
  line += " --out " + o.out + " --seed " + std::to_string(o.seed);
  for (const std::string& f : o.families) line += " --family " + f;
  for (const std::string& m : o.methods) line += " --method " + m;
  if (!o.scene.empty()) line += " --scene " + o.scene;
  if (o.fail_tolerance != 1e-6) line += " --fail-tolerance " + shortest(o.fail_tolerance);
  if (o.loops > 0) line += " --loops " + std::to_string(o.loops);
  return line;
}

std::string default_python() {
  if (access("/usr/bin/python3", X_OK) == 0) return "/usr/bin/python3";  // Debian's, with python3-matplotlib
  return "python3";
}

// The scene's queries as one family of cases (signed distance of each pair).
std::optional<bench::FamilyRun> scene_family(const std::string& path, std::string& error) {
  std::optional<LoadedScene> loaded = prepare_scene(path, error);
  if (!loaded) return std::nullopt;
  expand_all_pairs(*loaded->scene, loaded->built);  // all pairs: each answered pair is a case
  bench::FamilyRun run;
  const Scene& scene = *loaded->scene;
  run.name = "scene:" + (scene.name.empty() ? fs::path(path).stem().string() : scene.name);
  const auto start = std::chrono::steady_clock::now();
  for (std::size_t i = 0; i < scene.queries.size(); ++i) {
    const QuerySpec& q = scene.queries[i];
    if (is_continuous(q.type)) {  // a sweep, not a pair at rest: `hedra bench --continuous` times those
      ++run.dropped;
      run.notes.push_back("query " + std::to_string(i) + " (" + to_string(q.type) +
                          "): continuous queries are benchmarked by --continuous, not from a scene");
      continue;
    }
    bench::BenchCase c;
    c.family = run.name;
    c.label = scene.bodies[q.a].name + " / " + scene.bodies[q.b].name;
    c.a = *loaded->built.shapes[scene.bodies[q.a].shape];
    c.b = *loaded->built.shapes[scene.bodies[q.b].shape];
    c.pose_a = loaded->built.poses[q.a];
    c.pose_b = loaded->built.poses[q.b];
    c.reference = reference_answer(loaded->built, i);
    if (!c.reference.exact.ok) {
      ++run.dropped;
      run.notes.push_back("query " + std::to_string(i) + " (" + c.label +
                          "): no reference: " + c.reference.exact.reason);
      continue;
    }
    run.cases.push_back(std::move(c));
  }
  run.reference_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return run;
}

// Creates `dir` and opens each output's temporary file there (an unwritable
// directory fails before minutes of work); nothing when it cannot, said on err.
std::optional<std::vector<AtomicFile>> open_outputs(const std::string& dir, const std::vector<std::string>& names,
                                                    std::ostream& err) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec || !fs::is_directory(dir)) {
    err << "hedra bench: " << dir << ": cannot create the output directory"
        << (ec ? ": " + ec.message() : std::string()) << "\n";
    return std::nullopt;
  }
  std::vector<AtomicFile> files;
  for (const std::string& name : names) {
    std::string error;
    std::optional<AtomicFile> file = AtomicFile::open((fs::path(dir) / name).string(), error);
    if (!file) {
      err << "hedra bench: " << error << "\n";
      return std::nullopt;
    }
    files.push_back(std::move(*file));
  }
  return files;
}

// Writes each file whole; false (said on err) when one cannot be.
bool commit_outputs(std::vector<AtomicFile>& files, const std::vector<std::string>& contents, std::ostream& err) {
  for (std::size_t k = 0; k < files.size(); ++k) {
    std::string error;
    if (!files[k].commit(contents[k], error)) {
      err << "hedra bench: " << error << "\n";
      return false;
    }
  }
  return true;
}

// Whether every name is in `known`; otherwise says which is not.
bool all_known(const std::vector<std::string>& names, const std::vector<std::string>& known, const char* option,
               std::ostream& err) {
  for (const std::string& name : names) {
    if (std::find(known.begin(), known.end(), name) != known.end()) continue;
    std::string list;
    for (const std::string& k : known) list += (list.empty() ? "" : ", ") + k;
    err << "hedra bench --continuous: " << option << ": unknown name '" << name << "' (available: " << list << ")\n";
    return false;
  }
  return true;
}

// --continuous: the sweep families (continuous.hpp) into continuous.csv and
// continuous.md; the table to stdout. Exit 1 when hedra tunnels, reports a
// false hit or fails.
int run_continuous_command(const BenchCommandOptions& options, std::string& out, std::ostream& err) {
  if (!all_known(options.families, bench::continuous_family_names(), "--family", err) ||
      !all_known(options.methods, bench::continuous_method_names(), "--method", err))
    return kExitBadInput;
  std::optional<std::vector<AtomicFile>> files = open_outputs(options.out, {"continuous.csv", "continuous.md"}, err);
  if (!files) return kExitBadInput;
  bench::ContinuousOptions co;
  co.seed = options.seed;
  co.quick = options.quick;
  co.families = options.families;
  co.methods = options.methods;
  co.peer_timeout_seconds = options.peer_timeout;
  co.loops = options.loops > 0 ? options.loops : (options.quick ? 3 : 7);
  const std::string date = bench::utc_now(), load_before = bench::load_average();
  const bench::ContinuousReport report = bench::run_continuous(co, err);
  const std::string header = "# hedra bench --continuous\n\n- command: `" + options.command_line +
                             "`\n- date: " + date + "\n- machine: " + bench::machine_description() +
                             "\n- load: " + load_before + " -> " + bench::load_average() + "\n\n";
  const std::string md = bench::continuous_markdown(report, header);
  if (!commit_outputs(*files, {bench::continuous_csv(report), md}, err)) return kExitBadInput;
  out = md;
  const int problems = bench::continuous_hedra_problems(report);
  err << "bench: " << options.out
      << ": continuous.csv, continuous.md; hedra tunnelled, false hits or failures: " << problems << "\n";
  return problems == 0 ? kExitOk : kExitCheckFailed;
}

int run_bench_command(const BenchCommandOptions& options, std::string& out, std::ostream& err) {
  const std::optional<QueryType> query = bench::find_bench_query(options.query);
  if (!query) {
    err << "hedra bench: --query: unknown query '" << options.query
        << "' (available: penetration, distance, intersect)\n";
    return kExitBadInput;
  }
  if (options.continuous) {
    if (*query != QueryType::penetration) {
      err << "hedra bench: --query " << options.query << " does not apply to --continuous (times of impact)\n";
      return kExitBadInput;
    }
    return run_continuous_command(options, out, err);
  }
  bench::BenchOptions bo;
  bo.query = *query;
  bo.workload.seed = options.seed;
  bo.workload.quick = options.quick;
  bo.families = options.families;
  bo.methods = options.methods;
  bo.scene = options.scene;
  bo.fail_tolerance = options.fail_tolerance;
  bo.peer_timeout_seconds = options.peer_timeout;
  bo.loops = options.loops > 0 ? options.loops : (options.quick ? 3 : 7);
  bo.loop_ns = options.quick ? 20000.0 : 50000.0;

  for (const std::string& f : options.families) {
    if (!bench::find_family(f)) {
      std::string names;
      for (const bench::FamilyInfo& info : bench::families())
        names += (names.empty() ? "" : ", ") + std::string(info.name);
      err << "hedra bench: --family: unknown family '" << f << "' (available: " << names << ")\n";
      return kExitBadInput;
    }
  }
  std::vector<bench::Method> methods;
  const std::vector<bench::Method> available = bench::all_methods(options.quick, *query);
  for (const bench::Method& m : available) {
    if (options.methods.empty() ||
        std::find(options.methods.begin(), options.methods.end(), m.name) != options.methods.end())
      methods.push_back(m);
  }
  for (const std::string& name : options.methods) {
    bool known = false;
    for (const bench::Method& m : available) known = known || m.name == name;
    if (!known) {
      std::string names;
      for (const bench::Method& m : available) names += (names.empty() ? "" : ", ") + m.name;
      err << "hedra bench: --method: unknown method '" << name << "' (available in this build for --query "
          << options.query << ": " << names << ")\n";
      return kExitBadInput;
    }
  }
  if (std::none_of(methods.begin(), methods.end(), [](const bench::Method& m) { return m.is_default; })) {
    // The headline compares with hedra's default: always run it.
    methods.insert(methods.begin(), available.front());
  }

  // The scene first: bad input is reported before the output directory is
  // touched.
  std::optional<bench::FamilyRun> scene_run;
  if (!options.scene.empty()) {
    std::string error;
    scene_run = scene_family(options.scene, error);
    if (!scene_run) {
      err << error << "\n";
      return kExitBadInput;
    }
  }

  std::optional<std::vector<AtomicFile>> files =
      open_outputs(options.out, {"summary.csv", "cases.csv", "stability.csv", "report.md", "plot_bench.py"}, err);
  if (!files) return kExitBadInput;

  bench::RunInfo info;
  info.command = options.command_line;
  info.date = bench::utc_now();
  info.machine = bench::machine_description();
  info.load_before = bench::load_average();
  info.seed = options.seed;
  info.quick = options.quick;
  info.source = options.scene.empty() ? "generated families" : "scene " + options.scene;

  std::vector<bench::FamilyRun> runs;
  if (scene_run) {
    bench::keep_asked_cases(*scene_run, bo);
    err << "bench: " << scene_run->name << ": " << scene_run->cases.size() << " queries with exact references";
    if (scene_run->skipped) err << ", " << scene_run->skipped << " not separated beyond the tolerance: not asked";
    err << "\n";
    runs.push_back(std::move(*scene_run));
  } else {
    runs = bench::generate_families(bo, err);
  }
  const bench::BenchReport report = bench::run_bench(bo, methods, std::move(runs), err);
  info.load_after = bench::load_average();

  const std::string md = bench::markdown_report(report, info);
  if (!commit_outputs(*files,
                      {bench::summary_csv(report), bench::cases_csv(report), bench::stability_csv(report), md,
                       std::string(bench::plot_script())},
                      err))
    return kExitBadInput;
  if (*query == QueryType::intersect && !options.no_plots) {
    err << "bench: no plots for --query intersect (verdicts only: no error to draw)\n";
  } else if (!options.no_plots) {
    const std::string python = options.python.empty() ? default_python() : options.python;
    const std::string problem = run_plots(python, (fs::path(options.out) / "plot_bench.py").string(), options.out);
    if (!problem.empty()) {
      err << "hedra bench: plots not made (" << problem
          << "); the CSV files and report.md are written. Install python3-matplotlib, or pass --no-plots.\n";
    } else {
      err << "bench: plots written to " << options.out << " (error_vs_time.png/.svg, stability.png/.svg)\n";
    }
  }
  out = md;
  const std::size_t failures = bench::hedra_failures(report);
  err << "bench: " << options.out << ": summary.csv, cases.csv, stability.csv, report.md; hedra failures: " << failures
      << "\n";
  return failures == 0 ? kExitOk : kExitCheckFailed;
}

}  // namespace

Subcommand add_bench_command(CLI::App& app) {
  auto options = std::make_shared<BenchCommandOptions>();
  CLI::App* command = app.add_subcommand(
      "bench",
      "Error against run time: hedra at several tolerances beside libccd, FCL and Bullet on generated families of "
      "hard cases (or a scene's queries), every answer judged against the exact reference; CSV, markdown and plots "
      "(exit 1 when hedra has a failure)");
  command->add_flag("--quick", options->quick, "A few cases per family (under a minute; the test suite's run)");
  command->add_flag(
      "--continuous", options->continuous,
      "Times of impact instead: sweep families (toi-thin-plate, toi-grazing, toi-rotating-bar, "
      "toi-initial-contact, toi-small-large, toi-far) with hedra_toi, hedra_shape_cast and the continuous "
      "peers (bullet_f64_continuous, fcl_ca_linear, ...), judged against the exact first contact; "
      "continuous.csv and continuous.md");
  command->add_option("--out", options->out, "Output directory (created if missing; default bench-results)")
      ->type_name("DIR");
  command->add_option("--seed", options->seed, "Seed of the generated cases (default 1)")->type_name("N");
  command
      ->add_option("--family", options->families,
                   "Run only this family (repeatable): poly-separated, poly-penetrating, touching, deep, parallel, "
                   "thin, scale, far, large-hull, rounded, curved, degenerate")
      ->type_name("NAME");
  command
      ->add_option("--method", options->methods,
                   "Run only this method (repeatable): hedra, hedra@1e-03 .. hedra@1e-12, or a peer's name "
                   "(ccd_gjk_epa, ccd_mpr, fcl_libccd, fcl_indep, bullet_f32_gjk_epa, ...; ccd_gjk under --query "
                   "intersect, which has no hedra@ sweep); hedra always runs")
      ->type_name("NAME");
  command->add_option("--scene", options->scene, "Benchmark this scene's queries instead of the families")
      ->type_name("FILE");
  command
      ->add_option("--query", options->query,
                   "The question asked of hedra and the peers: penetration (signed distance, every pair; the "
                   "default), distance (distance(), on the separated pairs only) or intersect (intersect(), the "
                   "verdict, every pair; libccd's ccdGJKIntersect is ccd_gjk)")
      ->type_name("QUERY");
  command
      ->add_option("--fail-tolerance", options->fail_tolerance,
                   "Distance error, relative to the pair's size, above which an answer is a failure (default 1e-6)")
      ->check(CLI::Range(1e-16, 1.0))
      ->type_name("X");
  command
      ->add_option("--peer-timeout", options->peer_timeout,
                   "Seconds a peer may take on one case, timing included, before it counts as a timeout (default 20)")
      ->check(CLI::Range(0.1, 3600.0))
      ->type_name("SECONDS");
  command->add_option("--loops", options->loops, "Timed loops per case and method (default 7, quick 3)")
      ->check(whole_number_in(1, 1000, "loop count"))
      ->type_name("N");
  command->add_flag("--no-plots", options->no_plots, "Write the CSV files and the report only");
  command->add_option("--python", options->python, "Python interpreter for the plots (default /usr/bin/python3)")
      ->type_name("PATH");
  return Subcommand{command, [options](std::string& out, std::ostream& err) {
                      options->command_line = command_text(*options);
                      return run_bench_command(*options, out, err);
                    }};
}

}  // namespace hedra::tool
