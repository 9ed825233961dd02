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

 public:
  /// Destroys the context a suite kept for the next (SphereAtlasTest keeps it).
  static void releaseContext() { context_.reset(); }
};

class GlTest : public GlSuite<> {};

/// The contexts suites keep are destroyed when the tests end, before the process's exit handlers:
/// destroyed among those, after Mesa's own, OSMesa crashed making no context current.
class KeptGlContexts : public ::testing::Environment {
 public:
  void TearDown() override {
    GlSuite<false>::releaseContext();
    GlSuite<true>::releaseContext();
  }
};
inline ::testing::Environment* const kKeptGlContexts = ::testing::AddGlobalTestEnvironment(new KeptGlContexts);

}  // namespace puff::test
