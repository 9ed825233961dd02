// A GL context shared by every test in a suite (creating one per test costs ~50 ms on llvmpipe).
#pragma once

#include <gtest/gtest.h>

#include <memory>

#include <puff/platform/gl_context.h>

#include "support/assert_ok.h"

namespace puff::test {

/// `Compatibility`: a compatibility-profile context, where the fixed path draws too. `Base`: the
/// gtest base (::testing::TestWithParam<T> for parameterized suites).
template <bool Compatibility = false, class Base = ::testing::Test>
class GlSuite : public Base {
 protected:
  static void SetUpTestSuite() {
    if (context_) {  // kept from an earlier suite; another suite's context may be current now
      context_->makeCurrent();
      return;
    }
    core::GlContextOptions o;
    if (Compatibility) o.profile = core::GlProfile::kCompatibility;
    auto c = core::createGlContext(o);
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

class GlTest : public GlSuite<> {};

}  // namespace puff::test
