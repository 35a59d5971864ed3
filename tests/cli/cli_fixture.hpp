// The fixture of the `hedra` end-to-end tests (hedra_cli_test.cpp,
// scene_cli_test.cpp): each case gets a fresh temporary directory, writes
// its input files there, runs the real binary (path baked in by CMake as
// HEDRA_EXE) with posix_spawn, stdout and stderr captured to files, and
// checks the contract of scene-format.md (exit code, nothing on stdout for
// bad input, stderr naming the file).
#pragma once

#include <fcntl.h>
#include <gtest/gtest.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <string>
#include <vector>

extern char** environ;

namespace hedra::cli_test {

namespace fs = std::filesystem;

struct RunResult {
  int exit_code = -1;  // -1: did not exit normally (signal)
  std::string out;
  std::string err;
};

inline std::string slurp(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

// Number of lines of `text` that start with `prefix`.
inline int count_lines(const std::string& text, const std::string& prefix) {
  std::istringstream in(text);
  int count = 0;
  for (std::string line; std::getline(in, line);) count += line.rfind(prefix, 0) == 0 ? 1 : 0;
  return count;
}

inline std::set<std::string> listing(const fs::path& directory) {
  std::set<std::string> names;
  for (const fs::directory_entry& entry : fs::directory_iterator(directory)) {
    names.insert(entry.path().filename().string());
  }
  return names;
}

class HedraCli : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() / ("hedra_cli_" + std::string(info->name()) + "_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_ / "work");
    work_ = dir_ / "work";
  }
  void TearDown() override { fs::remove_all(dir_); }

  // Writes `text` to work/<name> and returns its path.
  std::string write(const std::string& name, const std::string& text) {
    const fs::path path = work_ / name;
    std::ofstream(path, std::ios::binary) << text;
    return path.string();
  }

  RunResult run(const std::vector<std::string>& args) {
    const fs::path out_path = dir_ / "stdout.txt";
    const fs::path err_path = dir_ / "stderr.txt";
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
    posix_spawn_file_actions_addopen(&actions, 1, out_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_addopen(&actions, 2, err_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    std::vector<std::string> storage = {HEDRA_EXE};
    storage.insert(storage.end(), args.begin(), args.end());
    std::vector<char*> argv;
    for (std::string& arg : storage) argv.push_back(arg.data());
    argv.push_back(nullptr);
    pid_t pid = 0;
    RunResult result;
    const int spawned = posix_spawn(&pid, HEDRA_EXE, &actions, nullptr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    if (spawned != 0) {
      ADD_FAILURE() << "cannot run " << HEDRA_EXE;
      return result;
    }
    int status = 0;
    while (waitpid(pid, &status, 0) < 0) {
    }
    if (WIFEXITED(status)) result.exit_code = WEXITSTATUS(status);
    result.out = slurp(out_path);
    result.err = slurp(err_path);
    return result;
  }

  // Runs and expects exit code 2, empty stdout and stderr containing every
  // one of `needles`.
  RunResult expect_bad(const std::vector<std::string>& args, const std::vector<std::string>& needles) {
    RunResult result = run(args);
    EXPECT_EQ(result.exit_code, 2) << "stderr: " << result.err;
    EXPECT_EQ(result.out, "") << "stdout must stay empty on bad input";
    EXPECT_FALSE(result.err.empty());
    for (const std::string& needle : needles) {
      EXPECT_NE(result.err.find(needle), std::string::npos) << "stderr lacks '" << needle << "': " << result.err;
    }
    return result;
  }

  nlohmann::json run_json(const std::vector<std::string>& args) {
    const RunResult result = run(args);
    EXPECT_EQ(result.exit_code, 0) << "stderr: " << result.err;
    EXPECT_EQ(result.err, "");
    nlohmann::json document = nlohmann::json::parse(result.out, nullptr, /*allow_exceptions=*/false);
    EXPECT_FALSE(document.is_discarded()) << "stdout is not JSON: " << result.out;
    return document;
  }

  fs::path dir_;
  fs::path work_;
};

}  // namespace hedra::cli_test
