// The fixture every multi-process test shares: a fresh folder per test for the processes' output and run
// directories (kept when the test fails, for the post-mortem), and the processes it started, all SIGKILLed
// and reaped by pid when the test ends, whatever happened.
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "tests/support/process.hpp"

namespace swarmform::testing {

// --max-ticks for a run that a test ends itself (SIGTERM, end_reason interrupted) once the fault it set up
// has played out: lockstep runs the random walk at up to ~4,000 ticks/s, so a fixed length that outlasts a
// stall or a restart on one host ended before it on another (a rejoin never came: CI, 2026-12-04).
inline constexpr const char* kOpenEndedTicks = "1000000000";

class ProcessFixture : public ::testing::Test {
 protected:
  explicit ProcessFixture(std::string prefix) : prefix_(std::move(prefix)) {}

  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = std::filesystem::temp_directory_path() /
           (prefix_ + "-" + std::string(info->name()) + "-" + std::to_string(getpid()));
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override {
    processes_.clear();  // SIGKILL whatever still runs
    if (!HasFailure()) std::filesystem::remove_all(dir_);
  }

  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  Process& start(const std::vector<std::string>& argv, const std::string& name,
                 const std::vector<std::string>& env = {}) {
    processes_.push_back(std::make_unique<Process>(argv, path(name), env));
    return *processes_.back();
  }

  std::filesystem::path dir_;
  std::vector<std::unique_ptr<Process>> processes_;

 private:
  std::string prefix_;
};

}  // namespace swarmform::testing
