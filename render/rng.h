// Rng: a small per-pixel random number generator (PCG32, O'Neill 2014) for deterministic rendering.
//
// Parameters: pixel (index y * width + x), frame (animation frame index). The seed is a hash of both, so every
// pixel of every frame has its own independent stream and no state is shared between threads: the image does not
// depend on which thread renders which tile, nor in which order.
#pragma once
#include <cstdint>

namespace wobble::render {

class Rng {
 public:
  Rng(std::uint64_t pixel, std::uint32_t frame) {
    // splitmix64 finaliser of both inputs: neighbouring pixels get unrelated states.
    std::uint64_t z =
        pixel * 0x9E3779B97F4A7C15ull ^ (std::uint64_t{frame} + 0x632BE59BD9B4E019ull) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    state_ = z ^ (z >> 31);
    nextUint();
  }

  std::uint32_t nextUint() {
    const std::uint64_t old = state_;
    state_ = old * 6364136223846793005ull + kIncrement;
    const auto xorshifted = static_cast<std::uint32_t>(((old >> 18u) ^ old) >> 27u);
    const auto rot = static_cast<std::uint32_t>(old >> 59u);
    return (xorshifted >> rot) | (xorshifted << ((32u - rot) & 31u));
  }

  // Uniform in [0, 1): the top 24 bits, so the result is exactly representable and never rounds up to 1.
  float next() { return static_cast<float>(nextUint() >> 8) * 0x1p-24f; }

 private:
  static constexpr std::uint64_t kIncrement = 1442695040888963407ull;
  std::uint64_t state_;
};

}  // namespace wobble::render
