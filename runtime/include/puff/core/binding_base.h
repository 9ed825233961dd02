// Where Puff's binding points sit among a host's: one base for each kind, and every point of
// cel::Bindings and media::Bindings its kind's base plus a fixed offset (their headers list the
// offsets). A host that keeps its camera block on uniform buffer 0 and its albedo on texture unit 0
// moves Puff by moving three numbers. No GL: a plain struct.
#pragma once

namespace puff::core {

/// How many points of each kind Puff's offsets use past its base (cel's and media's together).
inline constexpr unsigned kUniformBufferSpan = 6, kStorageBufferSpan = 3, kTextureUnitSpan = 9;

struct BindingBase {
  /// The defaults keep clear of 0 and the few points above it that engines take first.
  unsigned uniformBuffer = 8;  ///< uniform buffer bindings base .. base + kUniformBufferSpan - 1
  unsigned storageBuffer = 4;  ///< shader storage buffer bindings base .. base + kStorageBufferSpan - 1
  unsigned textureUnit = 16;   ///< texture units base .. base + kTextureUnitSpan - 1
  bool operator==(const BindingBase&) const = default;
};

}  // namespace puff::core
