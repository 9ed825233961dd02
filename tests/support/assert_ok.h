// ASSERT_OK(expr) / EXPECT_OK(expr): a puff::Result (any T, void too) holds a value; on failure the
// test prints the expression and the error's message. Extra context streams on as with any gtest
// assertion: ASSERT_OK(r) << "frame " << f;
#pragma once

#include <gtest/gtest.h>

#include <puff/core/error.h>

namespace puff::test {

/// The predicate formatter behind ASSERT_OK and EXPECT_OK.
template <class T>
::testing::AssertionResult isOk(const char* expr, const Result<T>& r) {
  if (r.ok()) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << expr << " failed: " << r.error().message;
}

}  // namespace puff::test

#define ASSERT_OK(expr) ASSERT_PRED_FORMAT1(::puff::test::isOk, expr)
#define EXPECT_OK(expr) EXPECT_PRED_FORMAT1(::puff::test::isOk, expr)
