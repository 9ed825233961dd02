#include <algorithm>
#include <cmath>

#include <glm/common.hpp>

#include <puff/core/colour.h>
#include <puff/core/error.h>

namespace puff::core {

double srgbToLinear(double v) {
  const double a = std::abs(v);
  const double l = a <= 0.04045 ? a / 12.92 : std::pow((a + 0.055) / 1.055, 2.4);
  return std::copysign(l, v);
}

double linearToSrgb(double v) {
  const double a = std::abs(v);
  const double d = a <= 0.0031308 ? a * 12.92 : 1.055 * std::pow(a, 1.0 / 2.4) - 0.055;
  return std::copysign(d, v);
}

glm::vec3 srgbToLinear(glm::vec3 c) {
  return {static_cast<float>(srgbToLinear(double{c.r})), static_cast<float>(srgbToLinear(double{c.g})),
          static_cast<float>(srgbToLinear(double{c.b}))};
}

glm::vec3 linearToSrgb(glm::vec3 c) {
  return {static_cast<float>(linearToSrgb(double{c.r})), static_cast<float>(linearToSrgb(double{c.g})),
          static_cast<float>(linearToSrgb(double{c.b}))};
}

double luminance(glm::dvec3 c) { return 0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b; }

std::string_view toString(ViewTransform v) { return v == ViewTransform::kFilmic ? "filmic" : "standard"; }

std::optional<ViewTransform> parseViewTransform(std::string_view name) {
  if (name == "standard") return ViewTransform::kStandard;
  if (name == "filmic") return ViewTransform::kFilmic;
  return std::nullopt;
}

double filmicShoulder(double m) {
  constexpr double k = kFilmicKnee;
  if (m <= k) return m;
  return k + (1.0 - k) * (1.0 - std::exp(-(m - k) / (1.0 - k)));
}

glm::dvec3 viewTransform(glm::dvec3 c, ViewTransform view) {
  c = glm::max(c, glm::dvec3(0.0));
  if (view == ViewTransform::kFilmic) {
    const double m = std::max({c.r, c.g, c.b});
    if (m > kFilmicKnee) c *= filmicShoulder(m) / m;
  }
  c = glm::min(c, glm::dvec3(1.0));
  return {linearToSrgb(c.r), linearToSrgb(c.g), linearToSrgb(c.b)};
}

Image viewTransform(const Image& linear, ViewTransform view) {
  Image out = linear;
  if (linear.channels < 3) {
    for (float& v : out.pixels) v = static_cast<float>(linearToSrgb(std::clamp(double{v}, 0.0, 1.0)));
    return out;
  }
  const std::size_t n = static_cast<std::size_t>(linear.width) * linear.height;
  const auto ch = static_cast<std::size_t>(linear.channels);
  for (std::size_t i = 0; i < n; ++i) {
    const float* p = &linear.pixels[i * ch];
    const glm::dvec3 d = viewTransform(glm::dvec3(p[0], p[1], p[2]), view);
    float* q = &out.pixels[i * ch];
    q[0] = static_cast<float>(d.r);
    q[1] = static_cast<float>(d.g);
    q[2] = static_cast<float>(d.b);
    if (ch >= 4) q[3] = std::clamp(q[3], 0.0f, 1.0f);
  }
  return out;
}

std::string_view toString(AlphaMode a) { return a == AlphaMode::kPremultiplied ? "premultiplied" : "straight"; }

std::optional<AlphaMode> parseAlphaMode(std::string_view name) {
  if (name == "straight") return AlphaMode::kStraight;
  if (name == "premultiplied") return AlphaMode::kPremultiplied;
  return std::nullopt;
}

Image unpremultiply(const Image& premultiplied) {
  PUFF_CHECK(premultiplied.channels == 4);
  Image out = premultiplied;
  const std::size_t n = static_cast<std::size_t>(premultiplied.width) * premultiplied.height;
  for (std::size_t i = 0; i < n; ++i) {
    float* q = &out.pixels[i * 4];
    const float a = std::clamp(q[3], 0.0f, 1.0f);
    // Below 2^-16 a pixel holds no colour worth dividing out (a half float's alpha step near 0).
    const float inverse = a < 1.0f / 65536.0f ? 0.0f : 1.0f / a;
    for (int c = 0; c < 3; ++c) q[c] *= inverse;
    q[3] = a;
  }
  return out;
}

Image viewTransform(const Image& premultipliedLinear, ViewTransform view, AlphaMode alpha) {
  Image out = viewTransform(unpremultiply(premultipliedLinear), view);
  if (alpha == AlphaMode::kPremultiplied) {
    const std::size_t n = static_cast<std::size_t>(out.width) * out.height;
    for (std::size_t i = 0; i < n; ++i) {
      float* q = &out.pixels[i * 4];
      for (int c = 0; c < 3; ++c) q[c] *= q[3];
    }
  }
  return out;
}

Image decodeSrgb(const Image& display) {
  Image out = display;
  const auto ch = static_cast<std::size_t>(display.channels);
  const std::size_t colour = ch >= 4 ? 3 : ch;
  for (std::size_t i = 0; i < out.pixels.size(); ++i) {
    if (i % ch < colour) out.pixels[i] = static_cast<float>(srgbToLinear(double{out.pixels[i]}));
  }
  return out;
}

}  // namespace puff::core
