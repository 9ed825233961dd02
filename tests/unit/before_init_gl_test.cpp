// A host that makes a renderer before it loaded Puff's GL functions (no context, no initGl) gets
// an error from every create call saying what to do, not a crash (docs/embedding.md). This tier's
// process never makes a context, so Puff's GL functions are not loaded here.
#include <gtest/gtest.h>

#include <string>

#include <puff/cel/nailboards.h>
#include <puff/core/gl.h>
#include <puff/media/layers.h>
#include <puff/media/media.h>

namespace puff {
namespace {

template <class R>
void expectAskedForInitGl(const R& made, const std::string& call) {
  ASSERT_FALSE(made.ok()) << call;
  EXPECT_NE(made.error().message.find("call puff::core::initGl(getProcAddress) first"), std::string::npos)
      << call << ": " << made.error().message;
}

TEST(BeforeInitGl, EveryCreateReturnsAnErrorSayingToCallIt) {
  ASSERT_FALSE(core::glLoaded());
  expectAskedForInitGl(media::HostLayers::create(64, 64, 0.5f), "HostLayers::create");
  expectAskedForInitGl(media::Layers::create(64, 64, 1, 0.5f), "Layers::create");
  expectAskedForInitGl(media::Renderer::create(media::Settings{}), "media::Renderer::create");
  expectAskedForInitGl(cel::NailboardRenderer::create(), "cel::NailboardRenderer::create");
}

}  // namespace
}  // namespace puff
