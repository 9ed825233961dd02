#include <puffview/json_text.h>

#include <algorithm>

namespace puff::view {

namespace {

void print(std::string& out, const nlohmann::json& j, int indent) {
  const std::string pad(static_cast<std::size_t>(indent) + 2, ' ');
  const bool flat = j.is_array() && std::none_of(j.begin(), j.end(), [](const auto& v) { return v.is_structured(); });
  if (j.is_object() && !j.empty()) {
    out += "{\n";
    std::size_t i = 0;
    for (const auto& item : j.items()) {
      out += pad + nlohmann::json(item.key()).dump() + ": ";
      print(out, item.value(), indent + 2);
      out += ++i < j.size() ? ",\n" : "\n";
    }
    out += std::string(static_cast<std::size_t>(indent), ' ') + "}";
  } else if (j.is_array() && !j.empty() && !flat) {
    out += "[\n";
    for (std::size_t i = 0; i < j.size(); ++i) {
      out += pad;
      print(out, j[i], indent + 2);
      out += i + 1 < j.size() ? ",\n" : "\n";
    }
    out += std::string(static_cast<std::size_t>(indent), ' ') + "]";
  } else if (flat && !j.empty()) {
    out += "[";
    for (std::size_t i = 0; i < j.size(); ++i) out += (i ? ", " : "") + j[i].dump();
    out += "]";
  } else {
    out += j.dump();
  }
}

}  // namespace

std::string jsonText(const nlohmann::json& j) {
  std::string out;
  print(out, j, 0);
  return out;
}

}  // namespace puff::view
