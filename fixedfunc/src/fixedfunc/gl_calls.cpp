#include "gl_calls.h"

#include <string>
#include <vector>

#include <puff/fixedfunc/renderer.h>

namespace puff::fixedfunc {

namespace {
// Not thread-local: a GL context is current on one thread, and the log is a test's tool.
std::vector<std::string>* gCallLog = nullptr;
}  // namespace

void setCallLog(std::vector<std::string>* log) { gCallLog = log; }

namespace detail {

void recordCall(const char* name) {
  if (gCallLog != nullptr) gCallLog->emplace_back(name);
}

bool loaderReady() { return puff_glad_glGetString != nullptr; }

}  // namespace detail
}  // namespace puff::fixedfunc
