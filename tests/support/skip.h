// Skips that CI turns into failures. A test that cannot run here (no compatibility context, a tool
// setup.sh installs is missing) may skip on a developer's machine, but in CI, where setup.sh has
// installed everything, a skip would be a test that silently stopped running: .ci/run sets PUFF_CI,
// and the skip fails instead, with the same reason. Skips that are right everywhere (a test that
// needs llvmpipe on another driver, one that cannot run under AddressSanitizer, a window test
// outside Xvfb, which ctest runs as its own test) use GTEST_SKIP directly and say why there.
#pragma once

#include <cstdlib>

#include <gtest/gtest.h>

namespace puff::test {

inline bool inCi() {
  const char* v = std::getenv("PUFF_CI");
  return v != nullptr && *v != '\0' && *v != '0';
}

}  // namespace puff::test

/// GTEST_SKIP() locally; a failure with the same message where PUFF_CI is set. Returns from the
/// current function (a test body or SetUp) either way.
#define PUFF_SKIP_UNLESS_CI(message)                                               \
  do {                                                                             \
    if (::puff::test::inCi()) {                                                    \
      FAIL() << "cannot run, and CI (PUFF_CI) does not allow a skip: " << message; \
    }                                                                              \
    GTEST_SKIP() << message;                                                       \
  } while (0)
