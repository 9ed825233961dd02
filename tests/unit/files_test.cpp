// Output files (core/files.h): a run must fail before its work when its output
// cannot be written, and must clear the temporary files that killed runs left behind.
#include <puff/core/files.h>

#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <string>

#include "support/assert_ok.h"
#include "support/temp_dir.h"

namespace {

namespace fs = std::filesystem;

// DIR/.NAME.tmp-PID.png, as OutputTransaction::stage names it (appended: GCC 12 warns falsely,
// -Wrestrict, on a chain of operator+).
fs::path temp(const fs::path& dir, const std::string& name, pid_t pid) {
  std::string file = ".";
  file += name;
  file += ".tmp-";
  file += std::to_string(pid);
  file += ".png";
  return dir / file;
}

// A PID that no process has: a child's, after it has exited and been reaped.
pid_t deadPid() {
  const pid_t child = ::fork();
  if (child == 0) ::_exit(0);
  int status = 0;
  ::waitpid(child, &status, 0);
  return child;
}

TEST(OutputTransaction, StagingClearsTheTemporaryFilesOfRunsThatAreGone) {
  puff::test::ScopedTempDir dir("puff_files");
  const fs::path target = dir / "frame.png";
  const fs::path dead = temp(dir.path(), "frame.png", deadPid());
  const fs::path alive = temp(dir.path(), "frame.png", ::getppid());
  const fs::path other = temp(dir.path(), "other.png", deadPid());
  for (const fs::path& p : {dead, alive, other}) ASSERT_OK(puff::core::writeFileBytes(p, "x"));
  {
    puff::core::OutputTransaction tx;
    ASSERT_OK(puff::core::writeFileBytes(tx.stage(target), "frame"));
    ASSERT_OK(tx.commit());
  }
  EXPECT_FALSE(fs::exists(dead)) << "a dead run's temporary file for this target stays";
  EXPECT_TRUE(fs::exists(alive)) << "a live run's temporary file was removed";
  EXPECT_TRUE(fs::exists(other)) << "another target's temporary file was removed";
  EXPECT_EQ(*puff::core::readFileBytes(target), "frame");
}

// commit() hard-links each replaced target to NAME.bak-PID while it renames; a run killed then leaves
// them. The next transaction for the name removes a dead run's, keeps a live one's, and names by
// content (nameByContent) still find what killed runs left under the final name.
TEST(OutputTransaction, CommitClearsTheBackupsOfRunsThatAreGone) {
  puff::test::ScopedTempDir dir("puff_files");
  const fs::path target = dir / "atlas.json";
  ASSERT_OK(puff::core::writeFileBytes(target, "old"));
  const auto backup = [&](const std::string& name, pid_t pid) { return dir / (name + ".bak-" + std::to_string(pid)); };
  const fs::path dead = backup("atlas.json", deadPid()), alive = backup("atlas.json", ::getppid());
  const fs::path notOurs = dir / ("atlas.json.bak-" + std::to_string(deadPid()) + ".keep");
  // Named by content: "map.HASH.png" is only known at commit.
  const std::string content = "map bytes";
  const std::string named = "map." + puff::core::fnv1a64Hex(content).substr(0, 12) + ".png";
  const fs::path deadNamed = backup(named, deadPid());
  for (const fs::path& p : {dead, alive, notOurs, deadNamed}) ASSERT_OK(puff::core::writeFileBytes(p, "x"));
  {
    puff::core::OutputTransaction tx;
    const fs::path staged = tx.stage(dir / "map.png");
    ASSERT_OK(puff::core::writeFileBytes(staged, content));
    auto t = tx.nameByContent(staged);
    ASSERT_OK(t);
    EXPECT_EQ(t->filename().string(), named);
    ASSERT_OK(puff::core::writeFileBytes(tx.stage(target), "new"));
    ASSERT_OK(tx.commit());
  }
  EXPECT_FALSE(fs::exists(dead));
  EXPECT_FALSE(fs::exists(deadNamed));
  EXPECT_TRUE(fs::exists(alive));
  EXPECT_TRUE(fs::exists(notOurs));
  EXPECT_EQ(*puff::core::readFileBytes(dir / named), content);
  EXPECT_EQ(*puff::core::readFileBytes(target), "new");
  EXPECT_FALSE(fs::exists(dir / "map.png"));
}

TEST(OutputTransaction, ADirectoryNoFileCanBeMadeInIsRefusedBeforeAnyWork) {
  // /proc passes access(W_OK) for root, yet takes no new file.
  puff::core::OutputTransaction tx;
  auto r = tx.prepareDirectory("/proc");
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().message.rfind("/proc: cannot write: ", 0), 0u) << r.error().message;
  puff::test::ScopedTempDir dir("puff_files");
  EXPECT_OK(tx.prepareDirectory(dir.path()));
  EXPECT_TRUE(fs::is_empty(dir.path())) << "the probe file stayed";
}

}  // namespace
