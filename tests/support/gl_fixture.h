// A GL context shared by every test in a suite (creating one per test costs ~50 ms on llvmpipe).
#pragma once

#include <gtest/gtest.h>

#include <memory>

#include <puff/core/gl_context.h>

#include "support/assert_ok.h"

namespace puff::test {

class GlTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    if (context_) return;
    auto c = core::createGlContext({});
    ASSERT_OK(c);
    context_ = std::move(*c);
  }
  static void TearDownTestSuite() { context_.reset(); }
  void SetUp() override {
    ASSERT_NE(context_, nullptr);
    context_->makeCurrent();
  }
  static inline std::unique_ptr<core::GlContext> context_;
};

}  // namespace puff::test
