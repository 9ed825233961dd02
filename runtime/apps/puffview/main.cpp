// puffview: main parses and makes one call (DESIGN.md); the viewer lives in puffview_lib.
#include <cstdio>
#include <exception>
#include <new>
#include <variant>

#include <puffview/options.h>

int main(int argc, char** argv) {
  // Errors travel as puff::Error values; this catch is the last guard for what a library may
  // throw (out of memory, a system error), so even then the user gets one line, not an abort.
  try {
    auto parsed = puff::view::parse(argc, argv);
    if (const int* exitCode = std::get_if<int>(&parsed)) return *exitCode;
    return puff::view::run(std::get<puff::view::Options>(parsed));
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "puffview: error: out of memory\n");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "puffview: error: %s\n", e.what());
  }
  return 1;
}
