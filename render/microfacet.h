// The GGX (Trowbridge-Reitz) microfacet distribution and Smith's shadowing term for it (Walter, Marschner, Li and
// Torrance 2007, eqs. 33 and 34), shared by the coat (bsdf.cpp) and the rough dielectric (dielectric.cpp).
//   ggxD(cos_h, a2)      the density of microfacet normals at cosine cos_h to the normal, alpha^2 = a2
//   smithG1(cos_v, a2)   the share of microfacets seen from a direction at cosine cos_v (either side)
#pragma once
#include <cmath>
#include <numbers>

namespace wobble::render {

inline float ggxD(float cos_h, float a2) {
  const float d = cos_h * cos_h * (a2 - 1.0f) + 1.0f;
  return a2 / (std::numbers::pi_v<float> * d * d);
}

inline float smithG1(float cos_v, float a2) {
  const float c = std::abs(cos_v);
  return 2.0f * c / (c + std::sqrt(a2 + (1.0f - a2) * c * c));
}

}  // namespace wobble::render
