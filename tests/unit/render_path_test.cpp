// The render-path table: every list, parser and warning of the paths reads it (render/path.h).
#include <set>
#include <string>

#include <gtest/gtest.h>

#include <puff/render/path.h>
#include <puff/scene/scene.h>

namespace puff::render {
namespace {

TEST(RenderPathTable, EveryPathHasOneRowWhoseNameParsesBackToIt) {
  const auto& table = renderPathTable();
  ASSERT_EQ(table.size(), 3u);
  EXPECT_EQ(table.front().path, RenderPath::kCel) << "the default first";
  std::set<std::string> names;
  for (const RenderPathInfo& p : table) {
    SCOPED_TRACE(p.name);
    EXPECT_TRUE(names.insert(p.name).second) << "a name given twice";
    EXPECT_FALSE(p.description.empty());
    EXPECT_EQ(toString(p.path), p.name);
    EXPECT_EQ(parseRenderPath(p.name), p.path);
    EXPECT_EQ(&renderPathInfo(p.path), &p);
    ASSERT_NE(p.omissions, nullptr);
  }
  EXPECT_EQ(renderPathNames(), "cel, fixed, reference");
  EXPECT_EQ(renderPathNames("|"), "cel|fixed|reference");
  for (const char* other : {"", "Cel", "cel ", "celshaded", "ref"}) {
    EXPECT_EQ(parseRenderPath(other), std::nullopt) << '"' << other << '"';
  }
}

TEST(RenderPathTable, GamesAreOfferedThePathsSceneRendererMakesAndNotTheReference) {
  const std::vector<RenderPathInfo> paths = renderPaths();
  ASSERT_EQ(paths.size(), 2u);
  EXPECT_EQ(paths[0].path, RenderPath::kCel);
  EXPECT_EQ(paths[1].path, RenderPath::kFixed);
  for (const RenderPathInfo& p : paths) EXPECT_NE(p.create, nullptr) << p.name;
  EXPECT_EQ(renderPathInfo(RenderPath::kReference).create, nullptr) << "puff::eval makes the cel reference";
  // Motion blur: the media pass of the cel path blurs; the references model none, the fixed path
  // draws no media.
  EXPECT_TRUE(renderPathInfo(RenderPath::kCel).motionBlur);
  EXPECT_FALSE(renderPathInfo(RenderPath::kFixed).motionBlur);
  EXPECT_FALSE(renderPathInfo(RenderPath::kReference).motionBlur);
}

TEST(RenderPathTable, EachPathNamesWhatItLeavesOutOfAScene) {
  const scene::Scene bare;
  for (const RenderPathInfo& p : renderPathTable()) {
    EXPECT_TRUE(p.omissions(bare).empty()) << p.name << " leaves something out of an empty scene";
  }
  auto omitted = [](RenderPath path, const scene::Scene& s) {
    std::string all;
    for (const std::string& line : renderPathInfo(path).omissions(s)) {
      EXPECT_EQ(line.find('\n'), std::string::npos) << "one line each: " << line;
      all += line + "\n";
    }
    return all;
  };

  scene::Scene withMedia;
  withMedia.media.emplace();
  EXPECT_NE(omitted(RenderPath::kFixed, withMedia).find("/media is left out"), std::string::npos);
  EXPECT_NE(omitted(RenderPath::kReference, withMedia).find("physical reference"), std::string::npos);
  EXPECT_EQ(omitted(RenderPath::kCel, withMedia), "");

  scene::Scene shadowed;
  shadowed.style.shadows = true;
  EXPECT_NE(omitted(RenderPath::kFixed, shadowed).find("/style/shadows is left out"), std::string::npos);
  EXPECT_EQ(omitted(RenderPath::kReference, shadowed), "");
  EXPECT_EQ(omitted(RenderPath::kCel, shadowed), "");

  scene::Scene oriented;
  oriented.particles.push_back(scene::ParticleSpec{.oriented = true});
  EXPECT_NE(omitted(RenderPath::kFixed, oriented).find("oriented puffs do not turn"), std::string::npos);
  EXPECT_EQ(omitted(RenderPath::kCel, oriented), "");

  scene::Scene all = withMedia;
  all.style.shadows = true;
  all.particles = oriented.particles;
  EXPECT_EQ(renderPathInfo(RenderPath::kFixed).omissions(all).size(), 3u);
}

}  // namespace
}  // namespace puff::render
