#include <cstdio>
#include <exception>
#include <new>
#include <variant>

#include "options.h"

int main(int argc, char** argv) {
  // Errors travel as puff::Error values; this catch is the last guard for what a library may
  // throw (out of memory, a system error), so even then the user gets one line, not an abort,
  // and staged outputs are removed as the stack unwinds.
  try {
    auto parsed = puff::app::parse(argc, argv);
    if (const int* exitCode = std::get_if<int>(&parsed)) return *exitCode;
    return puff::app::run(std::get<puff::app::Options>(parsed));
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "puffrender: error: out of memory\n");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "puffrender: error: %s\n", e.what());
  }
  return 1;
}
