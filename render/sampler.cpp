// Padded Owen-scrambled Sobol and hashed independent samples (see sampler.h).
#include "render/sampler.h"

#include <algorithm>
#include <array>

namespace wobble::render {

std::string_view toString(SamplerKind kind) { return kind == SamplerKind::Sobol ? "sobol" : "independent"; }

bool parseSamplerKind(std::string_view name, SamplerKind& kind) {
  if (name == "sobol") kind = SamplerKind::Sobol;
  else if (name == "independent") kind = SamplerKind::Independent;
  else return false;
  return true;
}

namespace sobol {

namespace {

// Direction numbers of Sobol dimension 1 (primitive polynomial x + 1, m_1 = 1): v_0 = 1/2, v_k = v_{k-1} ^ v_{k-1}/2.
constexpr std::array<std::uint32_t, 32> kDimension1 = [] {
  std::array<std::uint32_t, 32> v{};
  v[0] = 0x80000000u;
  for (int k = 1; k < 32; ++k) v[k] = v[k - 1] ^ (v[k - 1] >> 1);
  return v;
}();

// Dimension 1's direction numbers bit-reversed, so that reverseBits(dimension1(i)) is a XOR of these.
constexpr std::array<std::uint32_t, 32> kDimension1Reversed = [] {
  std::array<std::uint32_t, 32> r{};
  for (int k = 0; k < 32; ++k)
    for (int b = 0; b < 32; ++b)
      if (kDimension1[k] & (1u << b)) r[k] |= 1u << (31 - b);
  return r;
}();

// "lowbias32" (Wellons): a full-avalanche 32-bit integer mix.
std::uint32_t mix(std::uint32_t x) {
  x ^= x >> 16;
  x *= 0x7FEB352Du;
  x ^= x >> 15;
  x *= 0x846CA68Bu;
  x ^= x >> 16;
  return x;
}

// The same XOR a byte of the index at a time: kByteTables[b][v] is the XOR of the directions of byte b's bits in v.
// (Shuffled indices have random high bits, so a loop over the bits would take 32 unpredictable branches.)
const std::array<std::array<std::uint32_t, 256>, 4> kByteTables = [] {
  std::array<std::array<std::uint32_t, 256>, 4> t{};
  for (int b = 0; b < 4; ++b)
    for (int v = 0; v < 256; ++v)
      for (int k = 0; k < 8; ++k)
        if (v & (1 << k)) t[b][v] ^= kDimension1Reversed[8 * b + k];
  return t;
}();

std::uint32_t dimension1Reversed(std::uint32_t index) {
  return kByteTables[0][index & 0xFF] ^ kByteTables[1][(index >> 8) & 0xFF] ^ kByteTables[2][(index >> 16) & 0xFF] ^
         kByteTables[3][index >> 24];
}

// The scramble in bit-reversed order: every step changes a bit only as a function of itself and the bits under it,
// so in the fraction's own order each bit is flipped as a function of the bits above it: a nested uniform scramble.
std::uint32_t scrambleReversed(std::uint32_t v, std::uint32_t seed) {
  v ^= v * 0x3D20ADEAu;
  v += seed;
  v *= (seed >> 16) | 1u;
  v ^= v * 0x05526C56u;
  v ^= v * 0x53A22864u;
  return v;
}

}  // namespace

std::uint32_t reverseBits(std::uint32_t v) {
  v = __builtin_bswap32(v);
  v = ((v >> 1) & 0x55555555u) | ((v & 0x55555555u) << 1);
  v = ((v >> 2) & 0x33333333u) | ((v & 0x33333333u) << 2);
  return ((v >> 4) & 0x0F0F0F0Fu) | ((v & 0x0F0F0F0Fu) << 4);
}

std::uint32_t dimension0(std::uint32_t index) { return reverseBits(index); }

std::uint32_t dimension1(std::uint32_t index) { return reverseBits(dimension1Reversed(index)); }

std::uint32_t owenScramble(std::uint32_t v, std::uint32_t seed) {
  return reverseBits(scrambleReversed(reverseBits(v), seed));
}

std::uint32_t hash(std::uint32_t a, std::uint32_t b) { return mix(a ^ mix(b + 0x9E3779B9u)); }

}  // namespace sobol

PixelSampler::PixelSampler(SamplerKind kind, std::uint64_t pixel, std::uint32_t frame)
    : kind_(kind),
      seed_(sobol::hash(sobol::hash(static_cast<std::uint32_t>(pixel), static_cast<std::uint32_t>(pixel >> 32)),
                        frame)) {}

PixelSampler::SlotSeeds PixelSampler::seeds(int slot) const {
  if (slot >= kCachedSlots) return hashSeeds(slot);
  const std::uint32_t bit = 1u << slot;
  if (!(cached_ & bit)) {
    cache_[slot] = hashSeeds(slot);
    cached_ |= bit;
  }
  return cache_[slot];
}

PixelSampler::SlotSeeds PixelSampler::hashSeeds(int slot) const {
  // One full mix per slot; the two coordinate seeds from it by a cheaper multiply-xorshift, which still spreads the
  // high bits into the low ones (the scramble's first step adds the seed, so its low bits matter most).
  const std::uint32_t s = sobol::hash(seed_, static_cast<std::uint32_t>(slot));
  const auto derive = [s](std::uint32_t k) {
    std::uint32_t v = (s ^ k) * 0x2C1B3C6Du;
    v ^= v >> 12;
    v *= 0x297A2D39u;
    return v ^ (v >> 15);
  };
  return {s, derive(0x68E31DA4u), derive(0xB5297A4Du)};
}

// Independent samples: one full-avalanche 64-bit mix (splitmix64's finalizer) of a counter made of (pixel seed, sample,
// slot) gives a slot's two coordinates, its high and low 32 bits: one 64-bit mix a 2D draw instead of four 32-bit
// ones. At one sample per pixel (the default) every draw is one of these.
Eigen::Vector2f PixelSampler::independent(std::uint32_t sample, int slot) const {
  std::uint64_t z = ((std::uint64_t{seed_} << 32) | sample) + static_cast<std::uint64_t>(slot) * 0x9E3779B97F4A7C15u;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9u;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBu;
  z ^= z >> 31;
  return {sobol::toUnitFloat(static_cast<std::uint32_t>(z >> 32)), sobol::toUnitFloat(static_cast<std::uint32_t>(z))};
}

// Sobol points of a slot: the sample order shuffled (an Owen scramble of the index keeps power-of-two prefixes aligned
// blocks of the sequence, so they stay nets), then each coordinate scrambled. Worked in bit-reversed order, where
// dimension 0 is the index itself, so the scrambles need no reversals in between; the sample's own reversal is
// shared by all the slots of a sample.
std::uint32_t PixelSampler::shuffledIndex(std::uint32_t sample, std::uint32_t seed) const {
  if (sample != last_sample_) {
    last_sample_ = sample;
    last_reversed_ = sobol::reverseBits(sample);
  }
  return sobol::reverseBits(sobol::scrambleReversed(last_reversed_, seed));
}

float PixelSampler::get1D(std::uint32_t sample, int slot) const {
  if (kind_ == SamplerKind::Independent) return independent(sample, slot).x();
  const SlotSeeds s = seeds(slot);
  const std::uint32_t index = shuffledIndex(sample, s.shuffle);
  return sobol::toUnitFloat(sobol::reverseBits(sobol::scrambleReversed(index, s.x)));
}

Eigen::Vector2f PixelSampler::get2D(std::uint32_t sample, int slot) const {
  if (kind_ == SamplerKind::Independent) return independent(sample, slot);
  const SlotSeeds s = seeds(slot);
  const std::uint32_t index = shuffledIndex(sample, s.shuffle);
  return {sobol::toUnitFloat(sobol::reverseBits(sobol::scrambleReversed(index, s.x))),
          sobol::toUnitFloat(sobol::reverseBits(sobol::scrambleReversed(sobol::dimension1Reversed(index), s.y)))};
}

}  // namespace wobble::render
