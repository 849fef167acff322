#include "sim/contact/colliders/collider.h"

namespace wobble {

void Collider::near(double t, const StateRef& x, double margin, std::vector<int>& out) const {
  out.clear();
  const int n = static_cast<int>(x.size() / 3);
  out.reserve(n);  // once: the list never reallocates while a body settles onto the collider
  for (int i = 0; i < n; ++i)
    if (const auto s = query(t, particle(x, i)); s && s->distance < margin) out.push_back(i);
}

bool Collider::mayBeNear(double, const Eigen::AlignedBox3d&, double) const { return true; }

}  // namespace wobble
