// The benchmarks' usage text: `--help` (or `-h`) prints it on stdout and exits 0, as every Puff
// tool does; any other argument a benchmark does not know prints it on stderr and exits 2.
#pragma once

#include <cstdio>
#include <cstring>

namespace puff::bench {

inline bool isHelp(const char* argument) { return !std::strcmp(argument, "--help") || !std::strcmp(argument, "-h"); }
/// Where the usage text goes for `argument`.
inline std::FILE* usageStream(const char* argument) { return isHelp(argument) ? stdout : stderr; }
/// The exit code after the usage text for `argument`.
inline int usageExit(const char* argument) { return isHelp(argument) ? 0 : 2; }

}  // namespace puff::bench
