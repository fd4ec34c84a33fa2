#pragma once
// Test fixture for porter-plan run as a subprocess: a scratch directory per test (removed
// afterwards), run() with stdout and stderr captured to files in it, file() to read them back.
// The including test target defines PORTER_PLAN_EXE (the porter-plan binary).

#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

namespace porter::test {

class PlanCliTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const std::string suite = ::testing::UnitTest::GetInstance()->current_test_info()->test_suite_name();
    dir_ = std::filesystem::temp_directory_path() / ("porter_" + suite + "_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  /// Runs porter-plan with `args`; stdout goes to stdout<tag>.txt and stderr to stderr<tag>.txt
  /// in dir_. Returns the exit code (-1 when it did not exit normally).
  int run(const std::string& args, const std::string& tag = "") const { return run_in("", args, tag); }
  /// run() with the working directory `cwd` ("": the test's own).
  int run_in(const std::string& cwd, const std::string& args, const std::string& tag = "") const {
    const std::string cmd = (cwd.empty() ? std::string() : "cd '" + cwd + "' && ") + std::string(PORTER_PLAN_EXE) +
                            " " + args + " > " + (dir_ / ("stdout" + tag + ".txt")).string() + " 2> " +
                            (dir_ / ("stderr" + tag + ".txt")).string();
    const int status = std::system(cmd.c_str());
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }
  /// Contents of a file in dir_ ("" when missing).
  std::string file(const std::string& name) const {
    std::ifstream in(dir_ / name);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
  }

  std::filesystem::path dir_;
};

}  // namespace porter::test
