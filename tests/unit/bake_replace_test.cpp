// A bake is replaced whole. puffbake (and puffbake cook) name every map level by its
// content, rename the sidecar into place last and only then remove the atlas it replaced
// (puffbake/src/bake/atlas_files.h). Here the real tool is killed with SIGKILL at each of its
// renames in turn (an LD_PRELOAD shim, tests/support/kill_at_rename.c), over an existing atlas:
// after every kill the directory's sidecar loads, and what it loads is the old atlas or the new
// one, every map of it, never a mix; the next whole run leaves exactly the new atlas's files.
#include <gtest/gtest.h>

#include <sys/wait.h>

#include <algorithm>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include <puff/core/atlas.h>
#include <puff/core/files.h>

#include "support/assert_ok.h"
#include "support/temp_dir.h"

namespace {

namespace fs = std::filesystem;

int runKilledAt(long renameNumber, const std::string& args) {
  // verify_asan_link_order: the shim comes before the ASan runtime in an ASan build.
  // exec: the shell becomes the tool, so the kill is the status std::system sees.
  const std::string cmd =
      "exec env LD_PRELOAD=" PUFF_KILL_AT_RENAME_SO " PUFF_KILL_AT_RENAME=" + std::to_string(renameNumber) +
      " ASAN_OPTIONS=verify_asan_link_order=0 " PUFFBAKE_EXE " " + args + " >/dev/null 2>&1";
  const int status = std::system(cmd.c_str());
  if (WIFSIGNALED(status)) return -WTERMSIG(status);
  return WIFEXITED(status) ? WEXITSTATUS(status) : 999;
}

// Every map level's pixels, in a fixed order.
std::vector<std::vector<float>> pixelsOf(const puff::core::Atlas& atlas) {
  std::vector<std::vector<float>> out;
  for (const auto& [name, levels] : atlas.maps) {
    for (const puff::core::Image& im : levels) out.push_back(im.pixels);
  }
  return out;
}

std::set<std::string> filesIn(const fs::path& dir) {
  std::set<std::string> names;
  for (const auto& e : fs::directory_iterator(dir)) names.insert(e.path().filename().string());
  return names;
}

void copyDir(const fs::path& from, const fs::path& to) {
  fs::remove_all(to);
  fs::copy(from, to, fs::copy_options::recursive);
}

class BakeReplace : public ::testing::Test {
 protected:
  // Kills `args` (which writes the atlas `sidecar`) at rename 1, 2, ... over a copy of `before`
  // until a run finishes; after each kill the sidecar must load as `oldPixels` or `newPixels`.
  // Returns the number of renames the whole run made.
  long killAtEveryRename(const fs::path& before, const fs::path& dir, const fs::path& sidecar, const std::string& args,
                         const std::vector<std::vector<float>>& oldPixels,
                         const std::vector<std::vector<float>>& newPixels) {
    int oldSeen = 0, newSeen = 0;
    for (long k = 1; k < 200; ++k) {
      SCOPED_TRACE("killed at rename " + std::to_string(k));
      copyDir(before, dir);
      const int rc = runKilledAt(k, args);
      auto atlas = puff::core::loadAtlas(sidecar);
      EXPECT_OK(atlas);
      if (!atlas.ok()) return k;
      const auto pixels = pixelsOf(*atlas);
      const bool isOld = pixels == oldPixels, isNew = pixels == newPixels;
      EXPECT_TRUE(isOld || isNew) << "the sidecar loads a mix of the old and the new atlas";
      oldSeen += isOld;
      newSeen += isNew;
      if (rc != -SIGKILL) {
        EXPECT_EQ(rc, 0);
        EXPECT_TRUE(isNew);
        EXPECT_GT(oldSeen, 0);  // the kills before the sidecar's rename left the old atlas
        return k - 1;
      }
    }
    ADD_FAILURE() << "the run never finished";
    return 0;
  }
  puff::test::ScopedTempDir dir_{"puff_bake_replace"};
};

TEST_F(BakeReplace, AKillAtAnyRenameLeavesTheOldAtlasOrTheNewWhole) {
  const std::string common = " -s 16 --flange 2 --supersample 1 --views 2 --name puff -o ";
  // The old atlas: spheres. The new one: lumpy puffs (every map differs).
  const fs::path old = dir_ / "old", fresh = dir_ / "new", work = dir_ / "work";
  ASSERT_EQ(runKilledAt(0, "bake -g sphere -n 2" + common + old.string()), 0);
  ASSERT_EQ(runKilledAt(0, "bake -g lumpy -n 2" + common + fresh.string()), 0);
  auto oldAtlas = puff::core::loadAtlas(old / "puff.json");
  auto newAtlas = puff::core::loadAtlas(fresh / "puff.json");
  ASSERT_OK(oldAtlas);
  ASSERT_OK(newAtlas);
  const auto oldPixels = pixelsOf(*oldAtlas), newPixels = pixelsOf(*newAtlas);
  ASSERT_NE(oldPixels, newPixels);

  const long renames = killAtEveryRename(old, work, work / "puff.json", "bake -g lumpy -n 2" + common + work.string(),
                                         oldPixels, newPixels);
  // 2 levels x 4 maps (a multi-view atlas has a back map), the contact sheet, a sheet of each
  // variation's 4 views, and the sidecar.
  EXPECT_EQ(renames, 12);
  // The finished run left the new atlas's files only: its sidecar, what that names, the contact sheets.
  std::set<std::string> expected = {"puff.json", "puff_contact.png", "puff_contact_v0.png", "puff_contact_v1.png"};
  for (const auto& [name, map] : newAtlas->desc.maps) expected.insert(map.levels.begin(), map.levels.end());
  EXPECT_EQ(filesIn(work), expected);
  // Content names: the same bake gives the same names, so the new atlas's files are those of `fresh`.
  EXPECT_EQ(filesIn(work), filesIn(fresh));

  // A killed run's files (renamed into place, its sidecar never) are removed by the next whole run,
  // which finds them in the killed run's pending list; a user's files are never removed, however
  // much their names look like an atlas's.
  copyDir(old, work);
  const std::vector<std::string> userFiles = {"puff_color.aaaaaaaaaaaa.png", "puff_color.mip9.0123456789ab.png",
                                              "puff_lod0.aaaaaaaaaaaa.ply", "notes.txt"};
  for (const std::string& f : userFiles) ASSERT_OK(puff::core::writeFileBytes(work / f, "mine"));
  ASSERT_EQ(runKilledAt(6, "bake -g lumpy -n 2" + common + work.string()), -SIGKILL);
  EXPECT_GT(filesIn(work).size(), filesIn(old).size() + userFiles.size());
  ASSERT_EQ(runKilledAt(0, "bake -g sphere -n 2" + common + work.string()), 0);
  std::set<std::string> expectedAfter = filesIn(old);
  expectedAfter.insert(userFiles.begin(), userFiles.end());
  EXPECT_EQ(filesIn(work), expectedAfter);
}

TEST_F(BakeReplace, CookingReplacesACookedAtlasWhole) {
  const std::string common = " -s 16 --flange 2 --supersample 1 --name puff -o ";
  const fs::path a = dir_ / "a", b = dir_ / "b", cookedOld = dir_ / "cooked-old", work = dir_ / "work";
  ASSERT_EQ(runKilledAt(0, "bake -g sphere -n 1" + common + a.string()), 0);
  ASSERT_EQ(runKilledAt(0, "bake -g lumpy -n 1" + common + b.string()), 0);
  ASSERT_EQ(runKilledAt(0, "cook " + (a / "puff.json").string() + " -o " + (cookedOld / "game.json").string()), 0);
  auto oldAtlas = puff::core::loadAtlas(cookedOld / "game.json");
  auto newAtlas = puff::core::loadAtlas(b / "puff.json");
  ASSERT_OK(oldAtlas);
  ASSERT_OK(newAtlas);
  const long renames = killAtEveryRename(cookedOld, work, work / "game.json",
                                         "cook " + (b / "puff.json").string() + " -o " + (work / "game.json").string(),
                                         pixelsOf(*oldAtlas), pixelsOf(*newAtlas));
  EXPECT_EQ(renames, static_cast<long>(newAtlas->desc.mipLevels) * 3 + 1);
  std::set<std::string> files = filesIn(work);
  EXPECT_EQ(files.size(), static_cast<std::size_t>(newAtlas->desc.mipLevels) * 3 + 1);
  for (const std::string& f : files) {
    EXPECT_TRUE(f == "game.json" ||
                (f.rfind("game_", 0) == 0 && f.size() > 22 && f.compare(f.size() - 8, 8, ".puffimg") == 0))
        << f;
  }
}

}  // namespace
