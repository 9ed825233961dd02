// Saving an edited scene into the artist's own file (puff/scene/file_edit.h): the file's JSON is
// scanned for where each value lies, and only the values the edit changed are rewritten.
#include <puff/scene/file_edit.h>

#include <algorithm>
#include <cstddef>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include <puff/scene/write.h>

namespace puff::scene {

using nlohmann::json;

namespace {

// Where a JSON value lies in the text: [begin, end) bytes, and for an object its members (the last
// of a repeated key is the one a reader keeps), for an array its elements.
struct Span {
  std::size_t begin = 0, end = 0;
  bool object = false, array = false;
  struct Member {
    std::string key;
    std::size_t begin = 0;  // the key's opening quote
    std::unique_ptr<Span> value;
  };
  std::vector<Member> members;
  std::vector<std::unique_ptr<Span>> elements;

  const Member* member(const std::string& key) const {
    for (auto it = members.rbegin(); it != members.rend(); ++it)
      if (it->key == key) return &*it;
    return nullptr;
  }
};

// A scanner over text nlohmann has already parsed: it trusts the grammar and only finds the spans.
class Scanner {
 public:
  // A UTF-8 byte order mark before the value is skipped, as the reader skips it.
  explicit Scanner(std::string_view text) : t_(text), i_(text.starts_with("\xEF\xBB\xBF") ? 3 : 0) {}

  // Nesting deeper than this is refused before it is walked (the scene reader refuses it too).
  static constexpr int kMaxDepth = 128;

  // The value at the scanner's place; nullptr for nesting deeper than kMaxDepth.
  std::unique_ptr<Span> value(int depth = 0) {
    if (depth > kMaxDepth) return nullptr;
    skipSpace();
    auto span = std::make_unique<Span>();
    span->begin = i_;
    if (peek() == '{') {
      span->object = true;
      ++i_;
      skipSpace();
      while (peek() == '"') {
        Span::Member m;
        m.begin = i_;
        m.key = key();
        skipSpace();
        ++i_;  // ':'
        m.value = value(depth + 1);
        if (!m.value) return nullptr;
        span->members.push_back(std::move(m));
        skipSpace();
        if (peek() == ',') ++i_, skipSpace();
      }
      ++i_;  // '}'
    } else if (peek() == '[') {
      span->array = true;
      ++i_;
      skipSpace();
      while (i_ < t_.size() && peek() != ']') {
        span->elements.push_back(value(depth + 1));
        if (!span->elements.back()) return nullptr;
        skipSpace();
        if (peek() == ',') ++i_;
        skipSpace();
      }
      ++i_;  // ']'
    } else if (peek() == '"') {
      skipString();
    } else {
      while (i_ < t_.size() && std::string_view(",}] \t\r\n").find(t_[i_]) == std::string_view::npos) ++i_;
    }
    span->end = i_;
    return span;
  }

 private:
  char peek() const { return i_ < t_.size() ? t_[i_] : '\0'; }
  void skipSpace() {
    while (i_ < t_.size() && std::string_view(" \t\r\n").find(t_[i_]) != std::string_view::npos) ++i_;
  }
  void skipString() {
    ++i_;
    while (i_ < t_.size() && t_[i_] != '"') i_ += t_[i_] == '\\' ? 2 : 1;
    ++i_;
  }
  // A key as the reader sees it (escapes decoded).
  std::string key() {
    const std::size_t from = i_;
    skipString();
    return json::parse(t_.substr(from, i_ - from)).get<std::string>();
  }

  std::string_view t_;
  std::size_t i_;
};

// One change to the text: [begin, end) becomes `text` (an insertion when begin == end).
struct Edit {
  std::size_t begin, end;
  std::string text;
};

// A value on one line: {"a": 1, "b": [1, 2]}.
std::string oneLine(const json& v) {
  if (v.is_object()) {
    std::string out = "{";
    for (const auto& item : v.items())
      out += (out.size() > 1 ? ", " : "") + json(item.key()).dump() + ": " + oneLine(item.value());
    return out + "}";
  }
  if (v.is_array()) {
    std::string out = "[";
    for (const json& e : v) out += (out.size() > 1 ? ", " : "") + oneLine(e);
    return out + "]";
  }
  return v.dump();
}

class Editor {
 public:
  // New lines end as the file's do (CRLF where its first line break is one) and indent by its unit
  // (the first indented line's: a tab, or its run of spaces).
  explicit Editor(std::string_view text) : t_(text) {
    const std::size_t nl = text.find('\n');
    if (nl != std::string_view::npos && nl > 0 && text[nl - 1] == '\r') newline_ = "\r\n";
    for (std::size_t at = nl; at != std::string_view::npos; at = text.find('\n', at + 1)) {
      std::size_t to = at + 1;
      while (to < text.size() && (text[to] == ' ' || text[to] == '\t')) ++to;
      if (to == at + 1) continue;
      unit_ = text[at + 1] == '\t' ? "\t" : std::string(to - at - 1, ' ');
      break;
    }
  }

  void change(const Span& at, const json& before, const json& after) {
    if (before == after) return;
    if (at.object && before.is_object() && after.is_object()) return changeMembers(at, before, after);
    if (at.array && before.is_array() && after.is_array() && before.size() == after.size() &&
        at.elements.size() == after.size()) {
      for (std::size_t k = 0; k < after.size(); ++k) change(*at.elements[k], before[k], after[k]);
      return;
    }
    edits_.push_back({at.begin, at.end, render(after, at.begin, multiLine(at))});
  }

  std::string apply() {
    // From the end back, so that earlier offsets hold (no two edits start at one offset: each
    // starts at a value, a member or the end of a member's value, and none overlaps another).
    std::sort(edits_.begin(), edits_.end(), [](const Edit& a, const Edit& b) { return a.begin > b.begin; });
    std::string out(t_);
    for (const Edit& e : edits_) out.replace(e.begin, e.end - e.begin, e.text);
    return out;
  }

 private:
  void changeMembers(const Span& at, const json& before, const json& after) {
    // The file's members the edit keeps (a key written before and no longer is goes).
    std::vector<bool> kept(at.members.size(), true);
    bool anyKept = false;
    for (std::size_t k = 0; k < at.members.size(); ++k) {
      const std::string& key = at.members[k].key;
      kept[k] = after.contains(key) || !before.contains(key);
      anyKept = anyKept || kept[k];
    }
    if (!at.members.empty() && !anyKept) {
      edits_.push_back({at.begin, at.end, render(after, at.begin, multiLine(at))});
      return;
    }
    std::vector<std::pair<std::string, const json*>> added;
    for (const auto& item : after.items()) {
      const json* was = before.contains(item.key()) ? &before[item.key()] : nullptr;
      if (was && *was == item.value()) continue;
      if (const Span::Member* m = at.member(item.key())) {
        change(*m->value, was ? *was : json(), item.value());
      } else {
        added.emplace_back(item.key(), &item.value());
      }
    }
    removeRuns(at, kept);
    if (!added.empty()) add(at, added);
  }

  // Takes out each run of members not kept, with the commas between it and its neighbours: up to
  // the next kept member, or (a run at the end) from the end of the kept one before it.
  void removeRuns(const Span& at, const std::vector<bool>& kept) {
    const std::size_t n = at.members.size();
    for (std::size_t k = 0; k < n;) {
      if (kept[k]) {
        ++k;
        continue;
      }
      std::size_t last = k;
      while (last + 1 < n && !kept[last + 1]) ++last;
      if (last + 1 < n) {
        edits_.push_back({at.members[k].begin, at.members[last + 1].begin, ""});
      } else {
        edits_.push_back({at.members[k - 1].value->end, at.members[last].value->end, ""});
      }
      k = last + 1;
    }
  }

  // Appends `added` to object `at` after its last member: each on a line of its own where the
  // object's members are on lines of their own, and an object or array on one line where the last
  // member's value is.
  void add(const Span& at, const std::vector<std::pair<std::string, const json*>>& added) {
    if (at.members.empty()) {
      json all = json::object();
      for (const auto& [key, value] : added) all[key] = *value;
      edits_.push_back({at.begin, at.end, render(all, at.begin, false)});
      return;
    }
    const Span::Member& last = at.members.back();
    const bool lines = multiLine(at), valueLines = multiLine(*last.value);
    const std::string indent = lines ? indentAt(last.begin) : std::string();
    std::string text;
    for (const auto& [key, value] : added) {
      text += lines ? "," + newline_ + indent : ", ";
      text += json(key).dump() + ": " + render(*value, last.begin, valueLines);
    }
    edits_.push_back({last.value->end, last.value->end, text});
  }

  bool multiLine(const Span& s) const { return t_.substr(s.begin, s.end - s.begin).find('\n') != std::string::npos; }

  // The spaces before the first non-space character of the line holding `at`.
  std::string indentAt(std::size_t at) const {
    const std::size_t lineStart = t_.rfind('\n', at == 0 ? 0 : at - 1);
    const std::size_t from = lineStart == std::string_view::npos ? 0 : lineStart + 1;
    std::size_t to = from;
    while (to < t_.size() && (t_[to] == ' ' || t_[to] == '\t')) ++to;
    return std::string(t_.substr(from, to - from));
  }

  // `v` as text for the place `at`: one key a line, indented as that line and by the file's unit
  // a level (jsonText indents by two spaces), or on one line.
  std::string render(const json& v, std::size_t at, bool lines) const {
    if (!lines || !v.is_structured()) return oneLine(v);
    const std::string indent = indentAt(at), text = jsonText(v);
    std::string out;
    for (std::size_t from = 0; from <= text.size();) {
      std::size_t nl = text.find('\n', from);
      if (nl == std::string::npos) nl = text.size();
      std::size_t spaces = from;
      while (spaces < nl && text[spaces] == ' ') ++spaces;
      if (from > 0) out += newline_ + indent;
      for (std::size_t level = 0; level < (spaces - from) / 2; ++level) out += unit_;
      out.append(text, spaces, nl - spaces);
      from = nl + 1;
    }
    return out;
  }

  std::string_view t_;
  std::string newline_ = "\n", unit_ = "  ";
  std::vector<Edit> edits_;
};

}  // namespace

Result<std::string> editSceneText(const std::string& text, const json& before, const json& after) {
  json file;
  try {
    file = json::parse(text);
  } catch (const json::exception& e) {  // not JSON, or a number past a double's range
    return Error{std::string("not JSON: ") + e.what()};
  }
  if (!file.is_object()) return Error{"not a JSON object"};
  const std::unique_ptr<Span> root = Scanner(text).value();
  if (!root) return Error{"nested more than " + std::to_string(Scanner::kMaxDepth) + " arrays and objects deep"};
  Editor editor(text);
  editor.change(*root, before, after);
  return editor.apply();
}

}  // namespace puff::scene
