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

}  // namespace puff::core
