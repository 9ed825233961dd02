// The GPU media path against the exact reference on a small cloud of smoke, fire and dust.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <span>
#include <string>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include <puff/bake/detail.h>
#include <puff/core/detail_video.h>
#include <puff/core/image.h>
#include <puff/gl_api.h>
#include <puff/media/layers.h>
#include <puff/media/media.h>
#include <puff/reference/media_reference.h>
#include <puff/reference/metrics.h>

#include "reference_test_helpers.h"
#include "support/assert_ok.h"
#include "support/media_target.h"

namespace puff::reference_test {
namespace {

constexpr int kW = 96, kH = 64;
constexpr float kWallDistance = 6.0f;  // a wall behind the right part of the image, through the cloud
constexpr int kWallFrom = 60;          // first column of the wall
// Multiples of 1/255; the RGBA16F opaque layer holds them to within 2e-4.
const glm::vec3 kSky(0.4f, 0.6f, 0.8f), kWall(0.6f, 0.4f, 0.2f);

class ReferenceGpu : public test::MediaRendererTest {};

// The scene's frame: a turned camera (so the view transform matters) looking into the cloud.
media::Frame cloudFrame() {
  media::Frame f;
  f.view = glm::lookAt(glm::vec3(0.4f, 0.3f, 0.0f), glm::vec3(0.0f, 0.0f, -6.0f), glm::vec3(0.0f, 1.0f, 0.0f));
  f.projection = glm::perspective(glm::radians(45.0f), static_cast<float>(kW) / kH, 0.5f, 50.0f);
  f.nearPlane = 0.5f;
  f.farPlane = 50.0f;
  f.viewport.width = kW;
  f.viewport.height = kH;
  f.light.direction = glm::vec3(0.4f, 1.0f, 0.3f);
  f.light.color = glm::vec3(1.0f, 0.95f, 0.9f);
  f.ambient = glm::vec3(0.25f);
  return f;
}

// smoke, fire, dust (g 0.4) and a fire that turns into smoke over its life.
std::vector<media::Material> cloudMaterials() {
  media::Material dust = media::dustMaterial();
  dust.g = 0.4f;
  media::Material turning = media::fireMaterial();
  turning.name = "fire-to-smoke";
  turning.becomes = 0;
  turning.transitionStart = 0.2f;
  turning.transitionEnd = 0.8f;
  return {media::smokeMaterial(), media::fireMaterial(), dust, turning};
}

// 30 overlapping particles from a fixed LCG (no <random>: its distributions differ between libraries).
std::vector<media::Particle> cloudParticles() {
  std::uint32_t s = 12345u;
  auto next = [&s] {
    s = s * 1664525u + 1013904223u;
    return static_cast<float>(s >> 8) / 16777216.0f;
  };
  std::vector<media::Particle> ps;
  for (int i = 0; i < 30; ++i) {
    media::Particle p;
    // One draw a statement, z first: the order the measurements below were made in (a call's
    // arguments are evaluated in an order each compiler picks).
    const float z = next(), y = next(), x = next();
    p.position = glm::vec3(-2.2f + 4.4f * x, -1.3f + 2.6f * y, -7.5f + 3.0f * z);
    p.radius = 0.5f + 0.8f * next();
    p.material = static_cast<std::uint32_t>(i % 4);
    p.life = next();
    p.density = 0.6f + 0.8f * next();
    p.seed = s;
    ps.push_back(p);
  }
  return ps;
}

struct Opaque {
  std::vector<glm::vec3> color;
  std::vector<float> depth;
};

// The opaque layer the GPU draws (sky at infinity, the wall at kWallDistance), row 0 at the bottom.
Opaque cloudOpaque(const media::Frame& f, bool wall) {
  Opaque o;
  o.color.assign(kW * kH, kSky);
  o.depth.assign(kW * kH, 1.0f);
  if (wall) {
    for (int j = 0; j < kH; ++j)
      for (int i = kWallFrom; i < kW; ++i) {
        o.color[static_cast<std::size_t>(j) * kW + i] = kWall;
        o.depth[static_cast<std::size_t>(j) * kW + i] = static_cast<float>(linearDepth(f, kWallDistance));
      }
  }
  return o;
}

// The opaque layer alone as an image (row 0 at the top): the background coverage is measured against.
core::Image opaqueImage(const Opaque& o) {
  core::Image im(kW, kH, 4, 1.0f);
  for (int j = 0; j < kH; ++j)
    for (int i = 0; i < kW; ++i)
      for (int c = 0; c < 3; ++c) im.at(i, kH - 1 - j, c) = o.color[static_cast<std::size_t>(j) * kW + i][c];
  return im;
}

// Draws the scene through media::Layers at full resolution and reads the composed image back.
core::Image drawGpu(media::Renderer& r, const media::Frame& f, const Opaque& opaque, bool wall,
                    std::span<const media::Particle> particles, media::Method method) {
  auto layers = media::Layers::create(kW, kH, 1, 1.0f);
  EXPECT_OK(layers);
  const GLuint fbo = (*layers)->opaqueFramebuffer();
  glBindFramebuffer(GL_FRAMEBUFFER, fbo);
  glDisable(GL_SCISSOR_TEST);
  glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  glDepthMask(GL_TRUE);
  const glm::vec4 sky(kSky, 1.0f), wallColor(kWall, 1.0f);
  glClearNamedFramebufferfv(fbo, GL_COLOR, 0, &sky.x);
  glClearNamedFramebufferfi(fbo, GL_DEPTH_STENCIL, 0, 1.0f, 0);
  if (wall) {
    glEnable(GL_SCISSOR_TEST);
    glScissor(kWallFrom, 0, kW - kWallFrom, kH);
    glClearNamedFramebufferfv(fbo, GL_COLOR, 0, &wallColor.x);
    glClearNamedFramebufferfi(fbo, GL_DEPTH_STENCIL, 0, opaque.depth[kW - 1], 0);
    glDisable(GL_SCISSOR_TEST);
  }
  (*layers)->resolveOpaque();
  (*layers)->beginMedia();
  r.draw((*layers)->layerFrame(f), particles, method, (*layers)->mediaDepth());
  core::Framebuffer out = core::makeFramebuffer();
  core::Texture color = core::makeTexture(GL_TEXTURE_2D);
  glTextureStorage2D(color.get(), 1, GL_RGBA32F, kW, kH);
  glNamedFramebufferTexture(out.get(), GL_COLOR_ATTACHMENT0, color.get(), 0);
  const core::Viewport vp{0, 0, kW, kH};
  (*layers)->compose(out.get(), vp, f, {}, media::ComposeSettings{});
  std::vector<glm::vec4> px(static_cast<std::size_t>(kW) * kH);
  glGetTextureImage(color.get(), 0, GL_RGBA, GL_FLOAT, static_cast<GLsizei>(px.size() * sizeof(glm::vec4)), px.data());
  EXPECT_EQ(core::drainGlErrors(), "");
  core::Image im(kW, kH, 4);
  for (int j = 0; j < kH; ++j)
    for (int i = 0; i < kW; ++i)
      for (int c = 0; c < 4; ++c) im.at(i, kH - 1 - j, c) = px[static_cast<std::size_t>(j) * kW + i][c];
  return im;
}

// Draws straight into an RGBA32F target cleared to the opaque colours (the blend then leaves
// opaque * T + M in it, as the composition computes): the shader's arithmetic without the 16-bit
// layer, against an R32F depth texture holding exactly the reference's depths.
core::Image drawFloatTarget(media::Renderer& r, const media::Frame& f, const Opaque& opaque, bool wall,
                            std::span<const media::Particle> particles, media::Method method) {
  core::Framebuffer fbo = core::makeFramebuffer();
  core::Texture color = core::makeTexture(GL_TEXTURE_2D), depth = core::makeTexture(GL_TEXTURE_2D);
  glTextureStorage2D(color.get(), 1, GL_RGBA32F, kW, kH);
  glTextureStorage2D(depth.get(), 1, GL_R32F, kW, kH);
  glNamedFramebufferTexture(fbo.get(), GL_COLOR_ATTACHMENT0, color.get(), 0);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
  glTextureSubImage2D(depth.get(), 0, 0, 0, kW, kH, GL_RED, GL_FLOAT, opaque.depth.data());
  const glm::vec4 sky(kSky, 1.0f), wallColor(kWall, 1.0f);
  glDisable(GL_SCISSOR_TEST);
  glClearNamedFramebufferfv(fbo.get(), GL_COLOR, 0, &sky.x);
  if (wall) {
    glEnable(GL_SCISSOR_TEST);
    glScissor(kWallFrom, 0, kW - kWallFrom, kH);
    glClearNamedFramebufferfv(fbo.get(), GL_COLOR, 0, &wallColor.x);
    glDisable(GL_SCISSOR_TEST);
  }
  glBindFramebuffer(GL_FRAMEBUFFER, fbo.get());
  glViewport(0, 0, kW, kH);
  r.draw(f, particles, method, depth.get());
  std::vector<glm::vec4> px(static_cast<std::size_t>(kW) * kH);
  glGetTextureImage(color.get(), 0, GL_RGBA, GL_FLOAT, static_cast<GLsizei>(px.size() * sizeof(glm::vec4)), px.data());
  EXPECT_EQ(core::drainGlErrors(), "");
  core::Image im(kW, kH, 4);
  for (int j = 0; j < kH; ++j)
    for (int i = 0; i < kW; ++i)
      for (int c = 0; c < 3; ++c) im.at(i, kH - 1 - j, c) = px[static_cast<std::size_t>(j) * kW + i][c];
  return im;
}

core::Image drawReference(const media::Frame& f, const Opaque& opaque, std::span<const media::Particle> particles,
                          std::span<const media::Material> materials, const core::DetailVideo* temperature = nullptr,
                          const core::DetailVideo* opacity = nullptr, bool viewAxisOrder = false) {
  MediaReferenceInput in;
  in.viewAxisOrder = viewAxisOrder;
  in.frame = f;
  in.particles = particles;
  in.materials = materials;
  in.opaqueColor = opaque.color;
  in.opaqueDepth = opaque.depth;
  in.temperatureDetail = temperature;
  in.opacityDetail = opacity;
  return render(in);
}

// The pixels the wall covers, in core::Image order (row 0 at the top).
std::vector<bool> wallRegion() {
  std::vector<bool> m(kW * kH, false);
  for (int y = 0; y < kH; ++y)
    for (int x = kWallFrom; x < kW; ++x) m[static_cast<std::size_t>(y) * kW + x] = true;
  return m;
}

TEST_F(ReferenceGpu, TheShaderComputesTheReferenceModel) {
  // In a float target, composited in the renderer's own order (viewAxisOrder), the spherical
  // billboards must equal the reference up to 32-bit arithmetic and the GPU's tables: the phase
  // table (512 x 256, bilinear), the 1024-texel black-body ramp and the detail videos held as
  // 16-bit floats. Measured on llvmpipe: RMSE 7.5e-6 / max 4.3e-5 without detail, 1.35e-5 / 1.4e-4
  // with both videos, whose detail changes the image by RMSE 0.017 / max 0.11 (so a wrong hash,
  // window, row flip or time offset would show 1000 times over).
  const media::Frame f = cloudFrame();
  const auto particles = cloudParticles();
  auto materials = cloudMaterials();
  ASSERT_TRUE(renderer_->setMaterials(materials).ok());
  renderer_->setDetail(nullptr, nullptr);
  for (bool wall : {false, true}) {
    SCOPED_TRACE(wall ? "wall" : "no wall");
    const Opaque o = cloudOpaque(f, wall);
    const core::Image gpu = drawFloatTarget(*renderer_, f, o, wall, particles, media::Method::kSpherical);
    const core::Image ref = drawReference(f, o, particles, materials, nullptr, nullptr, true);
    const reference::ImageError e = reference::imageError(gpu, ref);
    std::printf("float target, no detail, %s: rmse %.2e max %.2e\n", wall ? "wall" : "no wall", e.rmse, e.maxAbs);
    EXPECT_LT(e.rmse, 5e-5);
    EXPECT_LT(e.maxAbs, 5e-4);
  }

  bake::DetailSpec spec;
  spec.size = 32;
  spec.frames = 8;
  spec.frequency = 2;
  spec.octaves = 3;
  auto temperature = bake::generateDetailVideo(spec);
  spec.seed = 7;
  auto opacity = bake::generateDetailVideo(spec);
  ASSERT_TRUE(temperature.ok() && opacity.ok());
  // Smoke with full density detail turns into dust.
  materials[3] = media::smokeMaterial();
  materials[3].becomes = 2;
  materials[3].detail = 1.0f;
  ASSERT_TRUE(renderer_->setMaterials(materials).ok());
  renderer_->setDetail(&*temperature, &*opacity);
  media::Frame later = f;
  later.time = 1.3f;
  for (bool wall : {false, true}) {
    SCOPED_TRACE(wall ? "wall" : "no wall");
    const Opaque o = cloudOpaque(later, wall);
    const core::Image gpu = drawFloatTarget(*renderer_, later, o, wall, particles, media::Method::kSpherical);
    const core::Image ref = drawReference(later, o, particles, materials, &*temperature, &*opacity, true);
    const core::Image plain = drawReference(later, o, particles, materials, nullptr, nullptr, true);
    const reference::ImageError e = reference::imageError(gpu, ref), detail = reference::imageError(plain, ref);
    std::printf("float target, detail videos, %s: rmse %.2e max %.2e (the videos change it by rmse %.4f)\n",
                wall ? "wall" : "no wall", e.rmse, e.maxAbs, detail.rmse);
    EXPECT_LT(e.rmse, 5e-5);
    EXPECT_LT(e.maxAbs, 1e-3);
    EXPECT_GT(detail.rmse, 0.01);
  }
  renderer_->setDetail(nullptr, nullptr);
}

// Curves over life give each particle its own tint and temperature. The shader takes
// them as the reference does (float target, the renderer's order: as TheShaderComputesTheReferenceModel),
// and they change the image by far more than the two differ. A tint of 0 leaves only what the medium
// absorbs, exactly as materials that neither scatter nor emit, on the textured billboards too; a
// particle's own temperature is exactly the material's T0 set to it.
TEST_F(ReferenceGpu, ParticlesTintsAndTemperaturesAreTheReferenceModels) {
  const media::Frame f = cloudFrame();
  const auto materials = cloudMaterials();
  ASSERT_TRUE(renderer_->setMaterials(materials).ok());
  renderer_->setDetail(nullptr, nullptr);
  const Opaque o = cloudOpaque(f, false);
  auto particles = cloudParticles();
  const auto plain = particles;
  for (std::size_t i = 0; i < particles.size(); ++i) {
    const float k = static_cast<float>(i) / static_cast<float>(particles.size());
    particles[i].tint = glm::vec3(1.0f - 0.8f * k, 0.3f + 0.5f * k, 0.6f);
    particles[i].temperature = i % 3 == 0 ? 0.0f : 1200.0f + 2400.0f * k;  // a third keep the material's
  }
  const core::Image gpu = drawFloatTarget(*renderer_, f, o, false, particles, media::Method::kSpherical);
  const core::Image ref = drawReference(f, o, particles, materials, nullptr, nullptr, true);
  const core::Image untinted = drawReference(f, o, plain, materials, nullptr, nullptr, true);
  const reference::ImageError e = reference::imageError(gpu, ref), change = reference::imageError(untinted, ref);
  std::printf("tints and temperatures: GPU against the reference rmse %.2e max %.2e (they change it by rmse %.4f)\n",
              e.rmse, e.maxAbs, change.rmse);
  EXPECT_LT(e.rmse, 5e-5);
  EXPECT_LT(e.maxAbs, 5e-4);
  EXPECT_GT(change.rmse, 0.02);

  std::vector<media::Material> dark = materials;
  for (media::Material& m : dark) {
    m.albedo = 0.0f;
    m.emission = 0.0f;
  }
  std::vector<media::Particle> black = plain, hot = plain;
  for (media::Particle& p : black) p.tint = glm::vec3(0.0f);
  for (media::Particle& p : hot) p.temperature = 1800.0f;
  std::vector<media::Material> at1800 = materials;
  for (media::Material& m : at1800) m.temperature = 1800.0f;
  for (media::Method method : {media::Method::kSpherical, media::Method::kPlanarTextured}) {
    SCOPED_TRACE(std::string(media::toString(method)));
    const core::Image tintedBlack = drawFloatTarget(*renderer_, f, o, false, black, method);
    const core::Image heated = drawFloatTarget(*renderer_, f, o, false, hot, method);
    ASSERT_TRUE(renderer_->setMaterials(dark).ok());
    const core::Image absorbing = drawFloatTarget(*renderer_, f, o, false, plain, method);
    ASSERT_TRUE(renderer_->setMaterials(at1800).ok());
    const core::Image materialHeat = drawFloatTarget(*renderer_, f, o, false, plain, method);
    ASSERT_TRUE(renderer_->setMaterials(materials).ok());
    const core::Image own = drawFloatTarget(*renderer_, f, o, false, plain, method);
    EXPECT_EQ(reference::imageError(tintedBlack, absorbing).maxAbs, 0.0) << "a tint of 0: only absorption";
    EXPECT_EQ(reference::imageError(heated, materialHeat).maxAbs, 0.0) << "its own T0 is the material's set to it";
    EXPECT_GT(reference::imageError(own, absorbing).rmse, 0.02) << "the cloud scatters and emits";
    EXPECT_GT(reference::imageError(own, heated).rmse, 0.005) << "1800 K is not the materials' temperature";
  }
}

TEST_F(ReferenceGpu, SphericalBillboardsMatchTheReferenceAndPlanarOnesDoNotAtAWall) {
  // The whole GPU path (media::Renderer + media::Layers at scale 1: RGBA16F opaque colour, depth24
  // resolved to R32F, RGBA16F layer, composition) against the exact reference, 30 overlapping
  // particles of smoke, fire, dust and fire turning into smoke, no detail video. Measured on
  // llvmpipe (RMSE / max):
  //   spherical, no wall  6.0e-4 / 0.0101      spherical, wall  4.5e-4 / 0.0098 (wall region 2.6e-4)
  //   planar, no wall     6.0e-4 / 0.0101      planar, wall     1.03e-2 / 0.119 (wall region 1.7e-2)
  // What the spherical error is made of (no wall):
  //   - order: the reference composited in the GPU's view-axis order instead of per ray differs
  //     from the exact one by 4.8e-4 / 0.0106: overlapping spheres whose centres' depth order is
  //     not their order along every ray;
  //   - the 16-bit float layer: the GPU against that view-axis-order reference, 4.1e-4 / 0.0026,
  //     darker on average by 2.7e-4 (llvmpipe's half-float blending looks like it rounds toward
  //     zero); in a float target the same comparison gives 7.5e-6 (TheShaderComputesTheReferenceModel);
  //   - the half-float (RGBA16F) opaque colour: the sky and wall round by at most 2e-4 (any colour
  //     in [0, 1] by at most 2.5e-4), times the transmittance;
  //   - the depth24 opaque depth: about 3e-6 world units at 6, far below everything else.
  // Thresholds: 2.5 times the measured RMSE, 3 times the largest order difference.
  const media::Frame f = cloudFrame();
  const auto materials = cloudMaterials();
  const auto particles = cloudParticles();
  ASSERT_TRUE(renderer_->setMaterials(materials).ok());
  renderer_->setDetail(nullptr, nullptr);
  const Opaque bare = cloudOpaque(f, false), walled = cloudOpaque(f, true);

  const core::Image refBare = drawReference(f, bare, particles, materials);
  const core::Image refWall = drawReference(f, walled, particles, materials);
  const core::Image sphericalBare = drawGpu(*renderer_, f, bare, false, particles, media::Method::kSpherical);
  const core::Image sphericalWall = drawGpu(*renderer_, f, walled, true, particles, media::Method::kSpherical);
  const core::Image planarBare = drawGpu(*renderer_, f, bare, false, particles, media::Method::kPlanar);
  const core::Image planarWall = drawGpu(*renderer_, f, walled, true, particles, media::Method::kPlanar);

  // The scene is not empty: most of the image is medium (3967 of 6144 pixels).
  const core::Image bareOpaque = opaqueImage(bare), wallOpaque = opaqueImage(walled);
  const std::vector<bool> covered = reference::coverageMask(refBare, bareOpaque);
  EXPECT_GT(std::count(covered.begin(), covered.end(), true), kW * kH / 2);

  const std::vector<bool> region = wallRegion();
  const reference::ImageError sphBare = reference::imageError(sphericalBare, refBare);
  const reference::ImageError sphWall = reference::imageError(sphericalWall, refWall);
  const reference::ImageError sphRegion = reference::imageError(sphericalWall, refWall, region);
  const reference::ImageError plaBare = reference::imageError(planarBare, refBare);
  const reference::ImageError plaWall = reference::imageError(planarWall, refWall);
  const reference::ImageError plaRegion = reference::imageError(planarWall, refWall, region);
  const reference::ImageError order =
      reference::imageError(drawReference(f, bare, particles, materials, nullptr, nullptr, true), refBare);
  const double iouSpherical = reference::coverageIoU(sphericalWall, refWall, wallOpaque);
  const double iouPlanar = reference::coverageIoU(planarWall, refWall, wallOpaque);
  std::printf("spherical: no wall rmse %.2e (psnr %.1f dB) max %.4f; wall rmse %.2e max %.4f, wall region %.2e\n",
              sphBare.rmse, sphBare.psnr, sphBare.maxAbs, sphWall.rmse, sphWall.maxAbs, sphRegion.rmse);
  std::printf("planar:    no wall rmse %.2e (psnr %.1f dB) max %.4f; wall rmse %.2e max %.4f, wall region %.2e\n",
              plaBare.rmse, plaBare.psnr, plaBare.maxAbs, plaWall.rmse, plaWall.maxAbs, plaRegion.rmse);
  std::printf("view-axis order alone: rmse %.2e max %.4f; coverage IoU spherical %.4f planar %.4f\n", order.rmse,
              order.maxAbs, iouSpherical, iouPlanar);

  for (const reference::ImageError& e : {sphBare, sphWall}) {
    EXPECT_LT(e.rmse, 1.5e-3);
    EXPECT_LT(e.maxAbs, 0.03);
  }
  // Away from surfaces planar billboards shade exactly like spherical ones.
  EXPECT_NEAR(plaBare.rmse, sphBare.rmse, 1e-5);
  // The wall cuts planar billboards whole: an error 23 times the spherical one, 66 times where the
  // wall is; the smoke's coverage IoU drops from 0.998 to 0.919.
  EXPECT_GT(plaWall.rmse, 10.0 * sphWall.rmse);
  EXPECT_GT(plaRegion.rmse, 0.01);
  EXPECT_GT(iouSpherical, 0.99);
  EXPECT_LT(iouPlanar, 0.95);
}

TEST_F(ReferenceGpu, TheGpuSortsByTheViewAxisTheReferenceAlongEachRay) {
  // ReferenceAnalytic.OverlappingSpheresCompositeInTheirOrderAlongTheRay's two spheres on the GPU:
  // it draws B over A everywhere (B's centre is nearer the camera plane), so on the rays where A's
  // chord comes first it equals the view-axis-order reference, not the exact one.
  media::Material ma = plain(0.8f), mb = plain(1.5f);
  ma.color = glm::vec3(1.0f, 0.0f, 0.0f);
  mb.color = glm::vec3(0.0f, 0.0f, 1.0f);
  const std::vector<media::Material> mats = {ma, mb};
  const media::Particle ps[] = {sphereAt({0, 0, -10}, 5.0f, 0), sphereAt({4, 0, -9}, 1.0f, 1)};
  ASSERT_TRUE(renderer_->setMaterials(mats).ok());
  renderer_->setDetail(nullptr, nullptr);
  media::Frame f = axisFrame(kW, kH);
  f.projection = glm::perspective(glm::radians(70.0f), static_cast<float>(kW) / kH, 0.5f, 50.0f);
  const Opaque o = cloudOpaque(f, false);
  const core::Image gpu = drawFloatTarget(*renderer_, f, o, false, ps, media::Method::kSpherical);
  const core::Image exact = drawReference(f, o, ps, mats);
  const core::Image viewAxis = drawReference(f, o, ps, mats, nullptr, nullptr, true);
  const reference::ImageError toViewAxis = reference::imageError(gpu, viewAxis);
  const reference::ImageError toExact = reference::imageError(gpu, exact);
  std::printf("two spheres: GPU against the view-axis order rmse %.2e, against the per-ray order rmse %.4f max %.4f\n",
              toViewAxis.rmse, toExact.rmse, toExact.maxAbs);
  EXPECT_LT(toViewAxis.rmse, 5e-5);
  EXPECT_GT(toExact.maxAbs, 0.05);
}

TEST_F(ReferenceGpu, GpuOpacityStaysContinuousAsFireStartsTurningIntoSmoke) {
  // Emitters upload detail 0 (as their albedo), like the reference. A shader that applies the
  // opacity detail only while the mixed emissive weight is below 1, with the mixed `detail` field
  // (for fire, 0.5 by default, otherwise unused), makes tau jump by 1 + 0.5 (2 D - 1) the moment fire
  // starts turning into smoke: with D = 0.1 everywhere the centre pixel goes from
  // (0.5601, 0.4458, 0.4184) at life 0.2499 to (0.5102, 0.4938, 0.5372) at 0.2501.
  media::Material fire = media::fireMaterial(), smoke = media::smokeMaterial();
  fire.becomes = 1;
  fire.transitionStart = 0.25f;
  fire.transitionEnd = 0.75f;
  fire.burn = 0.0f;
  smoke.detail = 1.0f;
  const std::vector<media::Material> mats = {fire, smoke};
  ASSERT_TRUE(renderer_->setMaterials(mats).ok());
  core::DetailVideo dark;
  dark.width = dark.height = 4;
  dark.frames = 1;
  dark.values.assign(16, 0.1f);
  renderer_->setDetail(nullptr, &dark);
  const media::Frame f = axisFrame(kW, kH);
  const Opaque o = cloudOpaque(f, false);
  for (float life : {0.2499f, 0.2501f, 0.5f}) {
    SCOPED_TRACE(life);
    media::Particle p = sphereAt({0, 0, -5}, 1.0f);
    p.life = life;
    const core::Image gpu = drawFloatTarget(*renderer_, f, o, false, std::span(&p, 1), media::Method::kSpherical);
    const core::Image ref = drawReference(f, o, std::span(&p, 1), mats, nullptr, &dark, true);
    EXPECT_LT(reference::imageError(gpu, ref).maxAbs, 1e-3);
  }
  renderer_->setDetail(nullptr, nullptr);
}

}  // namespace
}  // namespace puff::reference_test
