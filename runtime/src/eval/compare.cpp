#include <puff/eval/compare.h>

#include <puff/core/colour.h>
#include <puff/render/render.h>

#include <algorithm>
#include <cmath>

namespace puff::eval {

using render::RenderPath;
using render::SceneRenderer;
using scene::Scene;

Scene withoutParticles(const Scene& scene) {
  Scene s = scene;
  s.particles.clear();
  s.emitters.clear();
  if (s.simulation) s.simulation->emitters.clear();
  return s;
}

Scene restrictToFixedLimits(const Scene& scene, std::vector<std::string>* changes) {
  Scene s = scene;
  auto note = [&](const std::string& what) {
    if (changes) changes->push_back(what);
  };
  if (s.style.shadows) s.style.shadows = false, note("shadows off");
  if (!s.ambientGradient.empty()) s.ambientGradient.clear(), note("uniform ambient instead of the gradient");
  if (s.style.alignment != cel::Alignment::kViewPlane) {
    s.style.alignment = cel::Alignment::kViewPlane;
    note("view-plane billboards");
  }
  if (s.samples != 1) s.samples = 1, note("1 sample per pixel");
  if (s.media) s.media.reset(), note("no fire, smoke or dust media");
  return s;
}

Parity compareFrames(const core::Image& aLinear, const core::Image& aBareLinear, const core::Image& bLinear,
                     const core::Image& bBareLinear, float tolerance, core::Image* sideBySide) {
  // What a viewer sees: the masks and tones compare display values (the standard view transform).
  const core::Image a = core::viewTransform(aLinear, core::ViewTransform::kStandard);
  const core::Image aBare = core::viewTransform(aBareLinear, core::ViewTransform::kStandard);
  const core::Image b = core::viewTransform(bLinear, core::ViewTransform::kStandard);
  const core::Image bBare = core::viewTransform(bBareLinear, core::ViewTransform::kStandard);
  PUFF_CHECK(a.width == b.width && a.height == b.height && a.channels == 4 && b.channels == 4);
  PUFF_CHECK(aBare.width == a.width && bBare.width == a.width && aBare.height == a.height && bBare.height == a.height);
  PUFF_CHECK(aBare.channels == 4 && bBare.channels == 4);
  constexpr float kMaskThreshold = 1.0f / 64.0f;
  const int w = a.width, h = a.height;
  if (sideBySide) *sideBySide = core::Image(3 * w, h, 4);
  auto at = [](const core::Image& im, int x, int y, int c) {
    return im.pixels[(static_cast<std::size_t>(y) * im.width + x) * 4 + c];
  };
  auto differs = [&](const core::Image& im, const core::Image& bare, int x, int y) {
    for (int c = 0; c < 3; ++c)
      if (std::abs(at(im, x, y, c) - at(bare, x, y, c)) > kMaskThreshold) return true;
    return false;
  };
  Parity p;
  std::size_t within = 0, inUnion = 0;
  double sumDiff = 0.0;
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const bool inA = differs(a, aBare, x, y), inB = differs(b, bBare, x, y);
      float diff = 0.0f;
      for (int c = 0; c < 3; ++c) diff = std::max(diff, std::abs(at(a, x, y, c) - at(b, x, y, c)));
      p.maskA += inA, p.maskB += inB, p.both += inA && inB;
      if (inA || inB) ++inUnion, sumDiff += diff;
      if (inA && inB && diff <= tolerance) ++within;
      if (sideBySide) {
        auto put = [&](int column, float r, float g, float bl) {
          float* o = &sideBySide->pixels[(static_cast<std::size_t>(y) * 3 * w + column * w + x) * 4];
          o[0] = r, o[1] = g, o[2] = bl, o[3] = 1.0f;
        };
        put(0, at(a, x, y, 0), at(a, x, y, 1), at(a, x, y, 2));
        put(1, at(b, x, y, 0), at(b, x, y, 1), at(b, x, y, 2));
        if (inA != inB) {
          put(2, inA ? 1.0f : 0.2f, 0.2f, inB ? 1.0f : 0.2f);
        } else {
          const float d = std::min(1.0f, 4.0f * diff);
          put(2, 0.5f + 0.5f * d, 0.5f + 0.5f * d, 0.5f + 0.5f * d);
        }
      }
    }
  }
  p.iou = inUnion ? static_cast<double>(p.both) / static_cast<double>(inUnion) : 1.0;
  p.toneShare = p.both ? static_cast<double>(within) / static_cast<double>(p.both) : 1.0;
  p.meanAbsDiff = inUnion ? sumDiff / static_cast<double>(inUnion) : 0.0;
  return p;
}

}  // namespace puff::eval
