// Small string helpers shared by the readers and the command lines.
#pragma once

#include <cctype>
#include <string>
#include <string_view>

namespace puff::core {

/// `s` in ASCII lower case (other bytes unchanged).
inline std::string lower(std::string_view s) {
  std::string out(s);
  for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

/// A message of several lines (a shader compiler's log, several problems) as one line: its non-empty
/// lines joined by "; ", the first `maxLines` of them, then "(and N more)". A tool prints every
/// error on one line.
inline std::string oneLine(std::string_view text, std::size_t maxLines = 4) {
  std::string out;
  std::size_t kept = 0, dropped = 0;
  while (!text.empty()) {
    const std::size_t nl = text.find('\n');
    std::string_view line = text.substr(0, nl);
    text = nl == std::string_view::npos ? std::string_view() : text.substr(nl + 1);
    while (!line.empty() && (line.back() == '\r' || line.back() == ' ')) line.remove_suffix(1);
    if (line.empty()) continue;
    if (kept == maxLines) {
      ++dropped;
      continue;
    }
    out += (kept++ ? "; " : "");
    out += line;
  }
  if (dropped) out += " (and " + std::to_string(dropped) + " more)";
  return out;
}

}  // namespace puff::core
