// Sampler: the numbers in [0, 1) that drive one pixel's samples, as a pure function of (pixel, frame, sample index,
// dimension), so any thread can compute any sample and a frame is the same bytes however it is split.
//
// Kinds (SamplerKind):
//   Sobol        Owen-scrambled Sobol points, "padded" as in Burley 2020 ("Practical Hash-based Owen Scrambling")
//                and pbrt-v4's PaddedSobolSampler: every dimension slot (a 1D or 2D draw) takes Sobol dimensions
//                0 and 1 of its own shuffled and scrambled copy of the sequence, seeded by (pixel, frame, slot).
//                So within a slot the first 2^m samples of a pixel are a (0, m, 2)-net (one point in every
//                elementary interval), while slots and pixels are decorrelated. Error falls faster than 1/sqrt(n)
//                on smooth integrands; best with power-of-two sample counts.
//   Independent  hashed uniform random numbers (the renderer's sampler before Sobol): error falls as 1/sqrt(n).
// Dimension layout (SampleLayout) is fixed per scene: slot 0 is the pixel jitter, slot 1 the offset of the first
// hit's texture filter (texture.h); then, for every bounce, one 2D
// slot per light (suns, rectangles, the sky when sampled), one 1D slot for the BSDF lobe, one 2D slot for the BSDF
// direction and one 1D slot for Russian roulette. A slot's numbers never depend on what earlier slots were used for.
// Draws that only some scenes make sit in slots of their own far above those (kExtra on), so a scene without them
// keeps its numbers: the thin lens (kLens), the instant in the shutter (kTime, a 1D slot: motion blur, so within a
// pixel the times are stratified like any slot's draws), and per path vertex the free path in a medium and the choice
// of a gelatine's print layer (render/dielectric.h).
#pragma once
#include <cstdint>
#include <string_view>

#include <Eigen/Core>

namespace wobble::render {

enum class SamplerKind { Sobol, Independent };

// "sobol" / "independent"; parseSamplerKind returns false for any other name.
std::string_view toString(SamplerKind kind);
bool parseSamplerKind(std::string_view name, SamplerKind& kind);

// Which slot holds which draw, for a scene with `lights` light sources sampled at every bounce.
struct SampleLayout {
  int lights = 0;

  static constexpr int kPixel = 0, kTexture = 1, kFirstBounce = 2;
  int perBounce() const { return lights + 3; }
  int light(int bounce, int light_index) const { return kFirstBounce + bounce * perBounce() + light_index; }
  int bsdfLobe(int bounce) const { return kFirstBounce + bounce * perBounce() + lights; }
  int bsdfDirection(int bounce) const { return kFirstBounce + bounce * perBounce() + lights + 1; }
  int roulette(int bounce) const { return kFirstBounce + bounce * perBounce() + lights + 2; }
  static constexpr int kExtra = 1 << 20, kLens = kExtra - 1, kTime = kExtra - 2;
  static int medium(int vertex) { return kExtra + 2 * vertex; }
  static int print(int vertex) { return kExtra + 2 * vertex + 1; }
};

// The sample stream of one pixel of one frame. A slot's seeds are hashed at its first use and kept for the pixel's
// later samples (the first kCachedSlots slots; no allocation); further slots hash theirs on every draw.
class PixelSampler {
 public:
  static constexpr int kCachedSlots = 32;
  PixelSampler(SamplerKind kind, std::uint64_t pixel, std::uint32_t frame);

  float get1D(std::uint32_t sample, int slot) const;
  Eigen::Vector2f get2D(std::uint32_t sample, int slot) const;

 private:
  struct SlotSeeds {
    std::uint32_t shuffle, x, y;
  };
  SlotSeeds seeds(int slot) const;

  SlotSeeds hashSeeds(int slot) const;
  Eigen::Vector2f independent(std::uint32_t sample, int slot) const;
  std::uint32_t shuffledIndex(std::uint32_t sample, std::uint32_t seed) const;

  SamplerKind kind_;
  std::uint32_t seed_;
  mutable std::uint32_t cached_ = 0;                           // bit k: slot k's seeds are in cache_
  mutable std::uint32_t last_sample_ = 0, last_reversed_ = 0;  // the bit reversal of the sample drawn last
  mutable SlotSeeds cache_[kCachedSlots];
};

// The building blocks, exposed for tests.
namespace sobol {
// Sobol dimension 0 (van der Corput) and dimension 1 of `index`, as 32-bit fixed-point fractions.
std::uint32_t dimension0(std::uint32_t index);
std::uint32_t dimension1(std::uint32_t index);
std::uint32_t reverseBits(std::uint32_t v);
// Nested uniform (Owen) scramble of a 32-bit fraction: a random permutation of every dyadic interval's two halves,
// drawn from `seed` by a hash (Laine-Karras style, with Vegdahl's constants as in pbrt-v4).
std::uint32_t owenScramble(std::uint32_t value, std::uint32_t seed);
// A 32-bit integer hash of two values (for seeds).
std::uint32_t hash(std::uint32_t a, std::uint32_t b);
// Top 24 bits as a float in [0, 1): exact, never 1.
inline float toUnitFloat(std::uint32_t bits) { return static_cast<float>(bits >> 8) * 0x1p-24f; }
}  // namespace sobol

}  // namespace wobble::render
