// Numbers in messages: printf's "%g" (1000, 1e+05, 0.5, nan), short and exact enough for a value
// echoed back to the person who wrote it. Header-only: the libraries that use core's headers
// without linking it (puff::sim) call it too.
#pragma once

#include <cstdio>
#include <string>

namespace puff::core {

inline std::string numberText(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%g", v);
  return b;
}

}  // namespace puff::core
