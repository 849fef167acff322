// Giving back the room of the contact stages' lists. A landing cloth's lists hold millions of candidates for a step or
// two, each in several buffers kept from step to step: the room of those no stage reads any more goes back at once,
// so that a step holds about one full list at a time (docs/body-contact.md, "Cost").
#pragma once
#include <vector>

namespace wobble::collision {

// Frees a list's room (clear keeps it).
template <class T>
void release(std::vector<T>& list) {
  std::vector<T>().swap(list);
}

}  // namespace wobble::collision
