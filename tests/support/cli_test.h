// A fixture for running one of Puff's tools as a user would: a scratch directory per test, the
// tool run through the shell with stdout and stderr captured, and the one-line error contract.
#pragma once

#include <gtest/gtest.h>

#include <sys/wait.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include <puff/core/files.h>

#include "support/temp_dir.h"

namespace puff::test {

struct CliRun {
  int exitCode = -1;
  std::string out, err;
};

class CliTest : public ::testing::Test {
 protected:
  /// `exe`: the tool's path; `tool`: its name as its messages start ("puffbake").
  CliTest(std::string exe, std::string tool) : dir_(tool + "_cli"), exe_(std::move(exe)), tool_(std::move(tool)) {}

  /// A test may lock dir_/locked; unlocked here so that dir_ can be removed.
  void TearDown() override {
    std::error_code ec;
    std::filesystem::permissions(dir_ / "locked", std::filesystem::perms::owner_all, ec);
  }

  /// Runs the tool with `args` (shell syntax) and returns its exit code and output.
  CliRun run(const std::string& args) {
    const std::filesystem::path out = dir_ / "stdout.txt", err = dir_ / "stderr.txt";
    const std::string cmd = exe_ + " " + args + " >" + out.string() + " 2>" + err.string();
    const int status = std::system(cmd.c_str());
    CliRun r;
    r.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    r.out = *core::readFileBytes(out);
    r.err = *core::readFileBytes(err);
    std::filesystem::remove(out);
    std::filesystem::remove(err);
    return r;
  }

  /// Writes `text` to dir_/name (directories created) and returns the path.
  std::filesystem::path write(const std::string& name, const std::string& text) {
    const std::filesystem::path p = dir_ / name;
    std::filesystem::create_directories(p.parent_path());
    std::ofstream(p, std::ios::binary) << text;
    return p;
  }

  /// The one-line error contract: "TOOL: error: ..." containing `needle`, one line, exit `code`.
  void expectOneLineError(const CliRun& r, const std::string& needle, int code = 1) {
    EXPECT_EQ(r.exitCode, code) << r.err;
    EXPECT_EQ(r.err.rfind(tool_ + ": error: ", 0), 0u) << r.err;
    EXPECT_NE(r.err.find(needle), std::string::npos) << "stderr: " << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  }

  ScopedTempDir dir_;

 private:
  std::string exe_, tool_;
};

}  // namespace puff::test
