// Material parameter validation (see material.h).
#include "render/material.h"

#include <sstream>
#include <stdexcept>

namespace wobble::render {

void checkMaterial(const Material& m) {
  std::ostringstream why;
  if (!m.color.allFinite() || m.color.minCoeff() < 0 || m.color.maxCoeff() > 1) why << "color must be in [0, 1]; ";
  if (!(m.coat >= 0 && m.coat <= 1)) why << "coat must be in [0, 1]; ";
  if (!(m.ior > 1 && m.ior < 4)) why << "ior must be in (1, 4); ";
  if (!(m.roughness > 0 && m.roughness <= 1)) why << "roughness must be in (0, 1]; ";
  if (!why.str().empty()) throw std::invalid_argument("material '" + m.name + "': " + why.str());
}

}  // namespace wobble::render
