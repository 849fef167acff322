// Material parameter validation (see material.h).
#include "render/material.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace wobble::render {

void checkMaterial(const Material& m) {
  std::ostringstream why;
  if (!m.color.allFinite() || m.color.minCoeff() < 0 || m.color.maxCoeff() > 1) why << "color must be in [0, 1]; ";
  if (!(m.coat >= 0 && m.coat <= 1)) why << "coat must be in [0, 1]; ";
  if (m.dielectric) {
    if (!(m.roughness >= 0 && m.roughness <= 1)) why << "roughness must be in [0, 1]; ";
    if (!(m.ior > 1 && m.ior <= 4)) why << "ior must be in (1, 4]; ";
    if (!m.absorption.allFinite() || m.absorption.minCoeff() < 0) why << "absorption must be finite and >= 0; ";
    if (!(m.scatter >= 0 && std::isfinite(m.scatter))) why << "scatter must be finite and >= 0; ";
    if (!m.scatter_albedo.allFinite() || m.scatter_albedo.minCoeff() < 0 || m.scatter_albedo.maxCoeff() > 1)
      why << "scatter_albedo must be in [0, 1]; ";
    if (!(m.print >= 0 && m.print <= 1)) why << "print must be in [0, 1]; ";
  } else {
    if (!(m.ior > 1 && m.ior < 4)) why << "ior must be in (1, 4); ";
    if (!(m.roughness > 0 && m.roughness <= 1)) why << "roughness must be in (0, 1]; ";
  }
  if (!why.str().empty()) throw std::invalid_argument("material '" + m.name + "': " + why.str());
}

}  // namespace wobble::render
