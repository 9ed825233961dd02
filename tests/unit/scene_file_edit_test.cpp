// An edited scene saved into the artist's file (editSceneText): only what changed is rewritten, in
// the style of its place; the file's order, spacing, spellings and left-out defaults stay, and the
// text reads back as the edited scene.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include <puff/core/files.h>
#include <puff/scene/file_edit.h>
#include <puff/scene/read.h>
#include <puff/scene/write.h>

#include "support/assert_ok.h"

namespace puff::scene::file_edit {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// The lines of `text`, without their line breaks.
std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> out;
  std::size_t from = 0;
  for (std::size_t nl; (nl = text.find('\n', from)) != std::string::npos; from = nl + 1)
    out.push_back(text.substr(from, nl - from));
  out.push_back(text.substr(from));
  return out;
}

std::string edited(const std::string& text, const json& before, const json& after) {
  auto r = editSceneText(text, before, after);
  EXPECT_OK(r);
  return r ? *r : std::string();
}

// Every art scene, edited and not: the text stays byte for byte where nothing changed, and an edit
// of the camera's field of view changes its one line and reads back as the edited scene.
TEST(SceneFileEdit, AnArtSceneChangesOnlyWhereTheEditDid) {
  int scenes = 0;
  for (const auto& entry : fs::directory_iterator(fs::path(PUFF_SOURCE_DIR) / "art" / "scenes")) {
    if (entry.path().extension() != ".json") continue;
    SCOPED_TRACE(entry.path().filename().string());
    auto text = core::readFileBytes(entry.path());
    ASSERT_OK(text);
    auto scene = loadScene(entry.path(), PUFF_ART_DIR);
    ASSERT_OK(scene);
    const json before = toJson(*scene);
    EXPECT_EQ(edited(*text, before, before), *text);

    Scene changed = *scene;
    changed.camera.fovYDegrees += 5.0f;
    const json after = toJson(changed);
    const std::string out = edited(*text, before, after);
    const std::vector<std::string> was = lines(*text), now = lines(out);
    ASSERT_EQ(was.size(), now.size());
    int differ = 0;
    for (std::size_t k = 0; k < was.size(); ++k) {
      if (was[k] == now[k]) continue;
      ++differ;
      EXPECT_NE(now[k].find("\"fovY\""), std::string::npos) << now[k];
    }
    EXPECT_EQ(differ, 1);
    auto back = parseScene(json::parse(out), entry.path(), PUFF_ART_DIR);
    ASSERT_OK(back);
    EXPECT_EQ(toJson(*back), after);
    ++scenes;
  }
  EXPECT_GE(scenes, 20);
}

// A value that changed is rewritten where it stands; its neighbours keep their spelling.
TEST(SceneFileEdit, AChangedValueIsRewrittenInPlace) {
  const std::string text = R"({
  "output": {"width": 480, "background": "#2a1838"},
  "style": {"preset": "cel", "outlineWidth": 2}
})";
  const json before = {{"output", {{"width", 480}, {"background", {0.1, 0.2, 0.3}}}},
                       {"style", {{"preset", "cel"}, {"outlineWidth", 2}}}};
  json after = before;
  after["style"]["outlineWidth"] = 3;
  EXPECT_EQ(edited(text, before, after), R"({
  "output": {"width": 480, "background": "#2a1838"},
  "style": {"preset": "cel", "outlineWidth": 3}
})");
  // A colour the file spells "#rrggbb" and the edit changed is written as the writer writes it.
  after = before;
  after["output"]["background"] = {0.5, 0.5, 0.5};
  EXPECT_EQ(edited(text, before, after), R"({
  "output": {"width": 480, "background": [0.5, 0.5, 0.5]},
  "style": {"preset": "cel", "outlineWidth": 2}
})");
}

// A field the file leaves out (its default) goes at the end of its object once the edit moves it:
// on the object's line where it is on one line, on a line of its own, indented as its neighbours,
// where they are on lines of their own (and on one line where the last neighbour's value is); in an
// empty object, as the object's one member.
TEST(SceneFileEdit, AMovedDefaultGoesAtTheEndOfItsObject) {
  const std::string text =
      "{\n  \"style\": {\"preset\": \"cel\"},\n  \"light\": {\n    \"direction\": [0, 1, 0]\n  },\n"
      "  \"ambient\": {}\n}";
  const json before = {{"style", {{"preset", "cel"}, {"outlineWidth", 2}}},
                       {"light", {{"direction", {0, 1, 0}}, {"color", {1, 1, 1}}}},
                       {"ambient", {{"color", {0, 0, 0}}}}};
  json after = before;
  after["style"]["outlineWidth"] = 4;
  after["light"]["color"] = {0.5, 0.5, 0.5};
  after["light"]["shadow"] = {{"bias", 0.1}, {"kind", "map"}};
  after["ambient"]["color"] = {0.2, 0.2, 0.2};
  after["animation"] = {{"fps", 30}};
  EXPECT_EQ(edited(text, before, after), R"({
  "style": {"preset": "cel", "outlineWidth": 4},
  "light": {
    "direction": [0, 1, 0],
    "color": [0.5, 0.5, 0.5],
    "shadow": {"bias": 0.1, "kind": "map"}
  },
  "ambient": {"color": [0.2, 0.2, 0.2]},
  "animation": {"fps": 30}
})");
}

// A field the writer no longer writes goes with the comma before or after it: one in the middle,
// a run at the end, every member of an object.
TEST(SceneFileEdit, ADroppedFieldGoesWithItsComma) {
  const std::string text = R"({"a": 1, "b": 2, "c": 3, "d": {"x": 1, "y": 2}, "e": [1, 2]})";
  const json before = json::parse(text);
  json after = before;
  after.erase("b");
  EXPECT_EQ(edited(text, before, after), R"({"a": 1, "c": 3, "d": {"x": 1, "y": 2}, "e": [1, 2]})");
  after = before;
  after.erase("d");
  after.erase("e");
  EXPECT_EQ(edited(text, before, after), R"({"a": 1, "b": 2, "c": 3})");
  after = before;
  after["d"] = json::object();
  EXPECT_EQ(edited(text, before, after), R"({"a": 1, "b": 2, "c": 3, "d": {}, "e": [1, 2]})");
  // Dropped and added in one object: the new member follows the last one kept.
  after = before;
  after.erase("e");
  after["f"] = true;
  EXPECT_EQ(edited(text, before, after), R"({"a": 1, "b": 2, "c": 3, "d": {"x": 1, "y": 2}, "f": true})");
}

// Arrays of the same length change element by element; a longer or shorter one is written whole,
// on lines of its own where it was.
TEST(SceneFileEdit, ArraysChangeElementByElementOrWhole) {
  const std::string text = R"({
  "emitters": [
    {"count": 10, "seed": 1},
    {"count": 20, "seed": 2}
  ]
})";
  const json before = json::parse(text);
  json after = before;
  after["emitters"][1]["seed"] = 7;
  EXPECT_EQ(edited(text, before, after), R"({
  "emitters": [
    {"count": 10, "seed": 1},
    {"count": 20, "seed": 7}
  ]
})");
  after["emitters"].push_back({{"count", 5}});
  EXPECT_EQ(edited(text, before, after), R"({
  "emitters": [
    {
      "count": 10,
      "seed": 1
    },
    {
      "count": 20,
      "seed": 7
    },
    {
      "count": 5
    }
  ]
})");
}

// Keys with escapes are found as the reader reads them; a repeated key is the last one, as the
// reader keeps it; strings with brackets and commas in them are skipped whole.
TEST(SceneFileEdit, KeysAndStringsAreReadAsTheReaderReadsThem) {
  const std::string text = R"({"na\u006de": "a, {b}", "s": "x\", \"]", "n": 1, "n": 2})";
  const json before = json::parse(text);
  json after = before;
  after["name"] = "c";
  after["n"] = 3;
  EXPECT_EQ(edited(text, before, after), R"({"na\u006de": "c", "s": "x\", \"]", "n": 1, "n": 3})");
}

// A byte order mark stays where it is, before the object.
TEST(SceneFileEdit, AByteOrderMarkStays) {
  const std::string text = "\xEF\xBB\xBF{\"a\": 1}";
  EXPECT_EQ(edited(text, {{"a", 1}}, {{"a", 2}}), "\xEF\xBB\xBF{\"a\": 2}");
}

// New lines end and indent as the file's do: CRLF, tabs, four spaces.
TEST(SceneFileEdit, NewLinesEndAndIndentAsTheFilesDo) {
  const json before = {{"l", {{"d", 1}}}}, after = {{"l", {{"d", 1}}}, {"m", {{"e", {{"f", 2}}}}}};
  EXPECT_EQ(
      edited("{\r\n  \"l\": {\r\n    \"d\": 1\r\n  }\r\n}", before, after),
      "{\r\n  \"l\": {\r\n    \"d\": 1\r\n  },\r\n  \"m\": {\r\n    \"e\": {\r\n      \"f\": 2\r\n    }\r\n  }\r\n}");
  EXPECT_EQ(edited("{\n\t\"l\": {\n\t\t\"d\": 1\n\t}\n}", before, after),
            "{\n\t\"l\": {\n\t\t\"d\": 1\n\t},\n\t\"m\": {\n\t\t\"e\": {\n\t\t\t\"f\": 2\n\t\t}\n\t}\n}");
  EXPECT_EQ(edited("{\n    \"l\": {\n        \"d\": 1\n    }\n}", before, after),
            "{\n    \"l\": {\n        \"d\": 1\n    },\n    \"m\": {\n        \"e\": {\n            \"f\": 2\n"
            "        }\n    }\n}");
}

// Runs of fields dropped from the front, the middle and the end of an object on lines of its own,
// and every field of one: the lines go with them.
TEST(SceneFileEdit, DroppedRunsTakeTheirLines) {
  const std::string text = "{\n  \"a\": 1,\n  \"b\": 2,\n  \"c\": 3,\n  \"d\": 4,\n  \"e\": 5,\n  \"f\": 6\n}";
  const json before = json::parse(text);
  json after = before;
  for (const char* key : {"a", "b", "d", "f"}) after.erase(key);
  EXPECT_EQ(edited(text, before, after), "{\n  \"c\": 3,\n  \"e\": 5\n}");
  EXPECT_EQ(edited(text, before, {{"g", 7}}), "{\n  \"g\": 7\n}");
}

// A key the writer does not write (the file's own) stays where it is.
TEST(SceneFileEdit, AKeyTheWriterDoesNotWriteStays) {
  EXPECT_EQ(edited(R"({"a": 1, "x": 2})", {{"a", 1}}, {{"a", 3}}), R"({"a": 3, "x": 2})");
}

TEST(SceneFileEdit, TextThatIsNotAnObjectIsRefused) {
  EXPECT_FALSE(editSceneText("[1, 2]", json::array(), json::array()).ok());
  EXPECT_FALSE(editSceneText("{\"a\": ", json::object(), json::object()).ok());
  EXPECT_FALSE(editSceneText("{\"a\": 1e999}", json::object(), json::object()).ok()) << "a number past a double";
  const std::string deep = "{\"a\": " + std::string(200, '[') + std::string(200, ']') + "}";
  auto r = editSceneText(deep, json::object(), json::object());
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("nested more than 128"), std::string::npos) << r.error().message;
}

}  // namespace
}  // namespace puff::scene::file_edit
