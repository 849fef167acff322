// Giving back the room of the contact stages' lists. A landing cloth's lists hold millions of candidates for a step or
// two, each in several buffers kept from step to step: the room of those no stage reads any more goes back at once,
// so that a step holds about one full list at a time (docs/body-contact.md, "Cost"). A list of ordinary size keeps
// its room instead: the next step fills the pages it touched, where fresh ones would each cost a page fault.
#pragma once
#include <cstddef>
#include <vector>

namespace wobble::collision {

// The most bytes an emptied list keeps for the next step (recycle): a 256 x 256 cloth lying on itself lists about a
// million candidates a step (8 MB); a landing up to 6 million, whose room goes back.
constexpr std::size_t kKeptRoomBytes = std::size_t(16) << 20;

// Frees a list's room (clear keeps it).
template <class T>
void release(std::vector<T>& list) {
  std::vector<T>().swap(list);
}

// Empties a list for the next step, keeping its room unless that exceeds kKeptRoomBytes.
template <class T>
void recycle(std::vector<T>& list) {
  if (list.capacity() * sizeof(T) > kKeptRoomBytes) release(list);
  else list.clear();
}

}  // namespace wobble::collision
