// A set of contact pairs by their element (ContactPair::element: four vertex numbers, or a collider's and a point's),
// for "is this pair in the list already" when a search appends to backward Euler's pairs: open addressing, kept by its
// owner between calls so that it allocates nothing once grown. Sorting the list for a binary search instead cost
// several percent of a self-contacting cloth's step.
#pragma once
#include <array>
#include <cstdint>
#include <vector>

#include "sim/dynamics.h"

namespace wobble {

class ContactPairSet {
 public:
  // The elements of the pairs of `pairs` that keep(pair) (every pair when keep is left out).
  template <class Keep>
  void assign(const std::vector<ContactPair>& pairs, Keep&& keep) {
    std::size_t count = 0;
    for (const ContactPair& c : pairs) count += keep(c) ? 1 : 0;
    std::size_t size = 64;
    while (size < 2 * count) size *= 2;
    slots_.assign(size, kEmpty);
    mask_ = size - 1;
    for (const ContactPair& c : pairs) {
      if (!keep(c)) continue;
      std::size_t i = hash(c.element) & mask_;
      while (!same(slots_[i], kEmpty) && !same(slots_[i], c.element)) i = (i + 1) & mask_;
      slots_[i] = c.element;
    }
  }
  void assign(const std::vector<ContactPair>& pairs) {
    assign(pairs, [](const ContactPair&) { return true; });
  }
  bool contains(const std::array<int, 4>& e) const {
    for (std::size_t i = hash(e) & mask_;; i = (i + 1) & mask_) {
      if (same(slots_[i], e)) return true;
      if (same(slots_[i], kEmpty)) return false;
    }
  }
  // Whether two pairs' elements are the same, element by element: std::array's == became a call to memcmp per probe
  // here (3% of a folded cloth's step in a profile; 0.5% fewer instructions without).
  static bool same(const std::array<int, 4>& a, const std::array<int, 4>& b) {
    return a[0] == b[0] && a[1] == b[1] && a[2] == b[2] && a[3] == b[3];
  }

 private:
  // No pair's: a pair between bodies has surface vertices (>= 0), a collider's pair a collider's -1 - k then a point.
  static constexpr std::array<int, 4> kEmpty{-1, -1, -1, -1};
  static std::size_t hash(const std::array<int, 4>& e) {
    std::uint64_t h = 0x9e3779b97f4a7c15ull;
    for (const int v : e) h = (h ^ std::uint32_t(v)) * 0xff51afd7ed558ccdull;
    return std::size_t(h ^ (h >> 32));
  }
  std::vector<std::array<int, 4>> slots_{kEmpty};  // one empty slot: contains() before any assign finds nothing
  std::size_t mask_ = 0;
};

}  // namespace wobble
