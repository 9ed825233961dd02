// puff::fixedfunc: what the GL 1.x path draws, against analytic values: the puff texture of a unit
// sphere against N.L, and a billboard's disc and outline ring against the projection. The path in a
// host's context (GL 1.5 only, host state, the host's frame): fixedfunc_test.cpp.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <string>
#include <utility>
#include <vector>

#include <puff/gl_api.h>

#include <glm/gtc/matrix_transform.hpp>

#include <puff/fixedfunc/renderer.h>
#include <puff/mesh/mesh.h>

#include "fixedfunc_fixture.h"
#include "support/assert_ok.h"

namespace puff::fixedfunc::test {
namespace {

/// The puff texture, RGBA8, row 0 = texel row 0.
std::vector<unsigned char> readPuffTexture(const FixedRenderer& r) {
  const int n = 2 * r.cellSize();
  std::vector<unsigned char> texels(static_cast<std::size_t>(n) * n * 4);
  GLint previous = 0;
  glGetIntegerv(GL_TEXTURE_BINDING_2D, &previous);
  glBindTexture(GL_TEXTURE_2D, r.puffTexture());
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  glGetTexImage(GL_TEXTURE_2D, 0, GL_RGBA, GL_UNSIGNED_BYTE, texels.data());
  glBindTexture(GL_TEXTURE_2D, static_cast<GLuint>(previous));
  return texels;
}

// ---- 1. the texture-unit trick ------------------------------------------------------------------

TEST_F(FixedFuncTest, PuffTextureIsTwoToneNDotLWithCoverageInAlpha) {
  constexpr int kCell = 64;
  auto r = FixedRenderer::create(unitSphere(), kCell);
  ASSERT_OK(r);
  const float low = 0.3f, high = 0.9f;
  ASSERT_TRUE((*r)->setRamp(twoToneRamp(low, high)).ok());
  const FixedFrame frame = makeFrame();
  ASSERT_TRUE((*r)->drawFrame(frame, {}).ok());
  ASSERT_EQ(glGetError(), static_cast<GLenum>(GL_NO_ERROR));
  const std::vector<unsigned char> tex = readPuffTexture(**r);
  ASSERT_EQ(glGetError(), static_cast<GLenum>(GL_NO_ERROR));

  // Texel (i, j) of a cell sees the mesh at x, y in [-e, e]; the unit sphere's visible normal
  // there is (x, y, sqrt(1 - x^2 - y^2)) in camera space whatever the orientation (it is turned
  // about camera up), so N.L = x with the light along camera +x: lit from x = 0.5.
  const glm::vec3 lit = frame.ambientColor + frame.lightColor * high;
  const glm::vec3 unlit = frame.ambientColor + frame.lightColor * low;
  const float e = (*r)->cellExtent();
  const float texel = 2.0f * e / kCell;
  const float tol = 2.0f * texel;  // a texel or two
  const float colorTol = 3.0f / 255.0f;
  int litCount = 0, unlitCount = 0, outside = 0;
  for (int k = 0; k < 4; ++k) {
    for (int j = 0; j < kCell; ++j) {
      for (int i = 0; i < kCell; ++i) {
        const int tx = (k % 2) * kCell + i, ty = (k / 2) * kCell + j;
        const unsigned char* p = &tex[(static_cast<std::size_t>(ty) * 2 * kCell + tx) * 4];
        const glm::vec3 c(p[0] / 255.0f, p[1] / 255.0f, p[2] / 255.0f);
        const float x = -e + (i + 0.5f) * texel, y = -e + (j + 0.5f) * texel;
        const float rho = std::sqrt(x * x + y * y);
        SCOPED_TRACE("cell " + std::to_string(k) + " texel " + std::to_string(i) + "," + std::to_string(j));
        if (rho > 1.0f + tol) {
          ASSERT_EQ(p[3], 0) << "background has coverage";
          ++outside;
        } else if (rho < 1.0f - tol) {
          ASSERT_EQ(p[3], 255) << "inside the sphere without coverage";
          if (x > 0.5f + tol) {
            for (int ch = 0; ch < 3; ++ch) ASSERT_NEAR(c[ch], lit[ch], colorTol) << "lit side";
            ++litCount;
          } else if (x < 0.5f - tol) {
            for (int ch = 0; ch < 3; ++ch) ASSERT_NEAR(c[ch], unlit[ch], colorTol) << "unlit side";
            ++unlitCount;
          }
        }
      }
    }
  }
  EXPECT_GT(litCount, 4 * 300);
  EXPECT_GT(unlitCount, 4 * 1500);
  EXPECT_GT(outside, 4 * 500);
}

// A diagonal light: N.L = (x + y) / sqrt(2). With L along +x alone, a texture matrix holding L in
// its first column instead of its first row would give the same picture; this one would not.
TEST_F(FixedFuncTest, DiagonalLightBandFollowsNDotL) {
  constexpr int kCell = 64;
  auto r = FixedRenderer::create(unitSphere(), kCell);
  ASSERT_OK(r);
  ASSERT_TRUE((*r)->setRamp(twoToneRamp(0.3f, 0.9f)).ok());
  FixedFrame frame = makeFrame();
  frame.lightDirection = {1.0f, 1.0f, 0.0f};
  ASSERT_TRUE((*r)->drawFrame(frame, {}).ok());
  const std::vector<unsigned char> tex = readPuffTexture(**r);
  const glm::vec3 lit = frame.ambientColor + frame.lightColor * 0.9f;
  const float e = (*r)->cellExtent(), texel = 2.0f * e / kCell, tol = 2.0f * texel;
  int checked = 0, wrong = 0;
  for (int j = 0; j < kCell; ++j) {
    for (int i = 0; i < kCell; ++i) {
      const unsigned char* p = &tex[(static_cast<std::size_t>(j) * 2 * kCell + i) * 4];  // cell 0
      const float x = -e + (i + 0.5f) * texel, y = -e + (j + 0.5f) * texel;
      if (std::sqrt(x * x + y * y) > 1.0f - tol) continue;
      const float nl = (x + y) / std::sqrt(2.0f);
      if (std::abs(nl - 0.5f) < tol) continue;
      const bool isLit = std::abs(p[0] / 255.0f - lit.r) < 3.0f / 255.0f;
      ++checked;
      wrong += isLit != (nl > 0.5f) ? 1 : 0;
    }
  }
  EXPECT_GT(checked, 1500);
  EXPECT_EQ(wrong, 0);
}

TEST_F(FixedFuncTest, ShadingOffIsFlatDiffusePlusAmbient) {
  auto r = FixedRenderer::create(unitSphere(), 32);
  ASSERT_OK(r);
  const FixedFrame frame = makeFrame();
  FixedStyle style;
  style.shading = false;
  style.puffColor = {0.5f, 1.0f, 0.25f};
  ASSERT_TRUE((*r)->drawFrame(frame, {}, style).ok());
  const std::vector<unsigned char> tex = readPuffTexture(**r);
  const glm::vec3 expected = glm::min(glm::vec3(1.0f), frame.ambientColor + style.puffColor * frame.lightColor);
  const int n = 2 * (*r)->cellSize();
  for (int k = 0; k < 4; ++k) {
    const int cx = (k % 2) * 32 + 16, cy = (k / 2) * 32 + 16;  // cell centres: inside the sphere
    const unsigned char* p = &tex[(static_cast<std::size_t>(cy) * n + cx) * 4];
    for (int ch = 0; ch < 3; ++ch) EXPECT_NEAR(p[ch] / 255.0f, expected[ch], 3.0f / 255.0f) << "cell " << k;
    EXPECT_EQ(p[3], 255);
  }
}

TEST_F(FixedFuncTest, TheFourOrientationsDiffer) {
  constexpr int kCell = 64;
  auto r = FixedRenderer::create(mesh::generateLumpy({}), kCell);
  ASSERT_OK(r);
  FixedFrame frame = makeFrame();
  frame.lightDirection = {0.3f, 1.0f, 0.5f};
  ASSERT_TRUE((*r)->drawFrame(frame, {}).ok());
  const std::vector<unsigned char> tex = readPuffTexture(**r);
  auto texelOf = [&](int k, int i, int j) {
    return &tex[(static_cast<std::size_t>((k / 2) * kCell + j) * 2 * kCell + (k % 2) * kCell + i) * 4];
  };
  for (int a = 0; a < 4; ++a) {
    for (int b = a + 1; b < 4; ++b) {
      int differ = 0, covered = 0;
      for (int j = 0; j < kCell; ++j) {
        for (int i = 0; i < kCell; ++i) {
          const unsigned char *pa = texelOf(a, i, j), *pb = texelOf(b, i, j);
          covered += pa[3] > 127;
          differ += (pa[3] > 127) != (pb[3] > 127) || std::abs(pa[0] - pb[0]) > 8;
        }
      }
      EXPECT_GT(covered, kCell * kCell / 4) << "cell " << a << " is nearly empty";
      EXPECT_GT(differ, kCell * kCell / 50) << "cells " << a << " and " << b << " look alike";
    }
  }
}

// ---- 2. billboards and outlines -----------------------------------------------------------------

struct Rings {
  int body = 0, bodyBad = 0, ring = 0, ringBad = 0, background = 0, backgroundBad = 0, black = 0;
};

/// Classifies the frame around a billboard of the unit sphere centred on screen: inside `rBody`
/// the puff (not black, not background), between rBody and rOutline black, beyond background.
Rings classify(const std::vector<glm::vec4>& px, const glm::vec4& background, float rBody, float rOutline) {
  Rings out;
  const float margin = 1.5f;
  for (int y = 0; y < kSize; ++y) {
    for (int x = 0; x < kSize; ++x) {
      const glm::vec4 c = px[static_cast<std::size_t>(y) * kSize + x];
      const float rho = std::hypot(x + 0.5f - kSize / 2.0f, y + 0.5f - kSize / 2.0f);
      const bool isBlack = std::max({c.r, c.g, c.b}) < 0.02f;
      const bool isBackground = glm::length(glm::vec3(c - background)) < 0.02f;
      out.black += isBlack;
      if (rho < rBody - margin) {
        ++out.body;
        out.bodyBad += isBlack || isBackground;
      } else if (rho > rBody + margin && rho < rOutline - margin) {
        ++out.ring;
        out.ringBad += !isBlack;
      } else if (rho > rOutline + margin) {
        ++out.background;
        out.backgroundBad += !isBackground;
      }
    }
  }
  return out;
}

TEST_F(FixedFuncTest, BillboardCoversItsDiscAndTheOutlineIsARingBehindIt) {
  auto r = FixedRenderer::create(unitSphere(), 64);
  ASSERT_OK(r);
  ASSERT_TRUE((*r)->setRamp(twoToneRamp(0.3f, 0.9f)).ok());
  const FixedFrame frame = makeFrame();
  const float distance = 5.0f, size = 1.0f;
  // The sphere's radius size/2 at depth 5, projected: pixels per unit at that depth times 0.5.
  const float rBody = 0.5f * size / distance / std::tan(glm::radians(kFovY) / 2.0f) * (kSize / 2.0f);
  FixedStyle style;
  style.outlineScale = 1.3f;
  const float rOutline = rBody * style.outlineScale;
  const std::vector<Billboard> one = {{{0.0f, 0.0f, -distance}, size, 0}};

  ASSERT_TRUE((*r)->drawFrame(frame, one, style).ok());
  ASSERT_EQ(glGetError(), static_cast<GLenum>(GL_NO_ERROR));
  std::vector<glm::vec4> px = readFramebuffer();
  Rings rings = classify(px, frame.background, rBody, rOutline);
  EXPECT_GT(rings.body, 1000);
  EXPECT_EQ(rings.bodyBad, 0) << "the body is black or missing inside its disc (outline in front?)";
  EXPECT_GT(rings.ring, 200);
  EXPECT_EQ(rings.ringBad, 0) << "the outline ring is not black";
  EXPECT_EQ(rings.backgroundBad, 0) << "something drawn outside the outline";
  // Shaded: the lit (camera +x) side is brighter than the unlit side.
  const glm::vec4 right = px[static_cast<std::size_t>(kSize / 2) * kSize + kSize / 2 + 15];
  const glm::vec4 left = px[static_cast<std::size_t>(kSize / 2) * kSize + kSize / 2 - 15];
  EXPECT_NEAR(right.r, frame.ambientColor.r + 0.9f * frame.lightColor.r, 0.02f);
  EXPECT_NEAR(left.r, frame.ambientColor.r + 0.3f * frame.lightColor.r, 0.02f);

  // The same with an explicit, small d: still a ring of the same width on screen.
  style.outlineOffset = 0.05f;
  ASSERT_TRUE((*r)->drawFrame(frame, one, style).ok());
  rings = classify(readFramebuffer(), frame.background, rBody, rOutline);
  EXPECT_EQ(rings.bodyBad + rings.ringBad + rings.backgroundBad, 0);

  // Outlines off: the disc alone, and no black anywhere.
  style.outlines = false;
  ASSERT_TRUE((*r)->drawFrame(frame, one, style).ok());
  rings = classify(readFramebuffer(), frame.background, rBody, rBody);
  EXPECT_EQ(rings.black, 0);
  EXPECT_EQ(rings.bodyBad, 0);
  EXPECT_EQ(rings.backgroundBad, 0);
}

// §4.4: "the number of internal contours drawn decreases as d increases". A near puff A in front
// of a bigger far puff B, 0.5 units deeper, overlapping on screen: A's outline ring lies over B's
// body. With d < 0.5 the backing billboard is in front of B's body and draws an inner contour there;
// with d > 0.5 it is behind B's body and hidden.
TEST_F(FixedFuncTest, OffsetDDecidesWhetherAnInnerContourShows) {
  auto r = FixedRenderer::create(unitSphere(), 64);
  ASSERT_OK(r);
  const FixedFrame frame = makeFrame();
  const std::vector<Billboard> two = {{{0.0f, 0.0f, -5.0f}, 1.0f, 0}, {{0.5f, 0.0f, -5.5f}, 1.2f, 0}};
  const float pixelsPerUnitAt5 = 1.0f / 5.0f / std::tan(glm::radians(kFovY) / 2.0f) * (kSize / 2.0f);
  const float rBody = 0.5f * pixelsPerUnitAt5;
  FixedStyle style;
  style.outlineScale = 1.6f;
  auto blackInRing = [&](float d) {
    style.outlineOffset = d;
    EXPECT_TRUE((*r)->drawFrame(frame, two, style).ok());
    const std::vector<glm::vec4> px = readFramebuffer();
    int black = 0, checked = 0;
    // The right half of A's ring, on the row through both centres: inside B's disc.
    for (int x = kSize / 2 + static_cast<int>(rBody) + 2; x < kSize / 2 + static_cast<int>(1.6f * rBody) - 1; ++x) {
      const glm::vec4 c = px[static_cast<std::size_t>(kSize / 2) * kSize + x];
      black += std::max({c.r, c.g, c.b}) < 0.05f ? 1 : 0;
      ++checked;
    }
    EXPECT_GE(checked, 4);
    return std::pair{black, checked};
  };
  const auto [nearBlack, nearChecked] = blackInRing(0.2f);
  EXPECT_EQ(nearBlack, nearChecked) << "d = 0.2 < the gap: A's contour shows over B";
  const auto [farBlack, farChecked] = blackInRing(1.0f);
  EXPECT_EQ(farBlack, 0) << "d = 1 > the gap: B's body hides A's contour (of " << farChecked << " pixels)";
}

// The path's fill-rate floor (drawFloorFrame): its billboards as bare quads of their cells, alpha
// tested. On its first call it draws the puff texture; its frame is then drawFrame's with outlines
// off, pixel for pixel, over overlapping puffs of several sizes and cells; tints and outlines are
// not drawn; later calls keep the texture.
TEST_F(FixedFuncTest, TheFloorIsTheFramesBareQuadsWithoutOutlinesOrTints) {
  const FixedFrame frame = makeFrame();
  std::vector<Billboard> puffs;
  for (int k = 0; k < 9; ++k)
    puffs.push_back({{0.6f * static_cast<float>(k % 3) - 0.6f, 0.5f * static_cast<float>(k / 3) - 0.5f,
                      -4.0f - 0.3f * static_cast<float>(k)},
                     0.6f + 0.15f * static_cast<float>(k % 4),
                     k});
  auto floorFirst = FixedRenderer::create(unitSphere(), 64);
  ASSERT_OK(floorFirst);
  ASSERT_OK((*floorFirst)->drawFloorFrame(frame, puffs));
  const std::vector<glm::vec4> floor = readFramebuffer();
  auto r = FixedRenderer::create(unitSphere(), 64);
  ASSERT_OK(r);
  FixedStyle bare;
  bare.outlines = false;
  ASSERT_OK((*r)->drawFrame(frame, puffs, bare));
  const std::vector<glm::vec4> frameBare = readFramebuffer();
  EXPECT_EQ(floor, frameBare);
  int covered = 0;
  for (const glm::vec4& c : floor) covered += c != floor.back() ? 1 : 0;  // the top right corner: no puff
  EXPECT_GT(covered, static_cast<int>(floor.size()) / 10);                // the puffs are there
  // Tinted and outlined in the frame, neither in the floor; the texture as the first call drew it.
  for (Billboard& b : puffs) b.tint = glm::vec3(0.2f, 0.5f, 1.0f);
  ASSERT_OK((*floorFirst)->drawFloorFrame(frame, puffs));
  EXPECT_EQ(readFramebuffer(), frameBare);
  EXPECT_EQ(glGetError(), static_cast<GLenum>(GL_NO_ERROR));
}

}  // namespace
}  // namespace puff::fixedfunc::test
