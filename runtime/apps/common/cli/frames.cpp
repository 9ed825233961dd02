#include "cli/frames.h"

#include <algorithm>
#include <optional>

namespace puff::cli {

std::string OutputPattern::name(int frame) const {
  if (!numbered) return prefix;
  std::string number = std::to_string(frame);
  if (static_cast<int>(number.size()) < digits) number.insert(0, static_cast<std::size_t>(digits) - number.size(), '0');
  return prefix + number + suffix;
}

Result<OutputPattern> parseOutputPattern(const std::string& out, const std::string& flag) {
  OutputPattern p;
  std::size_t start = std::string::npos, end = 0;
  int found = 0;
  for (std::size_t i = 0; i < out.size();) {
    if (out[i] == '#') {
      std::size_t j = i;
      while (j < out.size() && out[j] == '#') ++j;
      ++found, start = i, end = j;
      p.digits = static_cast<int>(j - i);
      i = j;
    } else if (out[i] == '%') {
      // "%d" or "%0Nd" with N in 1..9.
      if (i + 1 < out.size() && out[i + 1] == 'd') {
        ++found, start = i, end = i + 2, p.digits = 0;
        i += 2;
      } else if (i + 3 < out.size() && out[i + 1] == '0' && out[i + 2] >= '1' && out[i + 2] <= '9' &&
                 out[i + 3] == 'd') {
        ++found, start = i, end = i + 4, p.digits = out[i + 2] - '0';
        i += 4;
      } else {
        ++i;
      }
    } else {
      ++i;
    }
  }
  if (found > 1) return Error{flag + " " + out + ": more than one frame-number pattern (%d, %0Nd or ###)"};
  if (found == 0) {
    p.prefix = out;
    return p;
  }
  p.numbered = true;
  p.prefix = out.substr(0, start);
  p.suffix = out.substr(end);
  return p;
}

Result<std::pair<int, int>> parseFrameRange(const std::string& text, const std::string& flag) {
  auto number = [](const std::string& s) -> std::optional<int> {
    if (s.empty() || s.size() > 9 || !std::all_of(s.begin(), s.end(), [](char c) { return c >= '0' && c <= '9'; })) {
      return std::nullopt;
    }
    return std::stoi(s);
  };
  const Error bad{flag + ": expected a frame N or a range A-B (0-based, inclusive), got \"" + text + "\""};
  const auto dash = text.find('-');
  if (dash == std::string::npos) {
    auto n = number(text);
    if (!n) return bad;
    return std::pair{*n, *n};
  }
  auto a = number(text.substr(0, dash)), b = number(text.substr(dash + 1));
  if (!a || !b) return bad;
  if (*a > *b) return Error{flag + " " + text + ": the range ends before it starts"};
  return std::pair{*a, *b};
}

}  // namespace puff::cli
