// Springs stored as arrays (structure of arrays), with their Hooke and damper forces and energy.
#pragma once
#include <cstdint>
#include <string_view>
#include <vector>

#include "sim/types.h"

namespace wobble {

enum class SpringType : std::uint8_t { Structural, Shear, Bending };
std::string_view toString(SpringType type);

struct Springs {
  std::vector<int> a, b;       // endpoint particle indices
  std::vector<double> rest;    // rest length
  std::vector<double> ks, kd;  // stiffness (N/m), damping along the spring (N s/m)
  std::vector<SpringType> type;

  void add(int pa, int pb, double rest_length, double stiffness, double damping, SpringType t);
  // Appends other with its particle indices shifted by offset (used when bodies are joined in one system).
  void append(const Springs& other, int offset);
  std::size_t size() const { return a.size(); }
  std::size_t count(SpringType t) const;
  // The springs in the order order[0], order[1], ...
  Springs permuted(const std::vector<int>& order) const;
};

// f += Hooke and damper forces of every spring (course-framework formulas; equal and opposite on a, b).
void addSpringForces(const Springs& s, const VecX& x, const VecX& v, VecX& f);
// The same for springs [begin, end).
void addSpringForces(const Springs& s, int begin, int end, const VecX& x, const VecX& v, VecX& f);

// Elastic energy sum 1/2 ks (|xa - xb| - rest)^2.
double springEnergy(const Springs& s, const VecX& x);

// Largest |l - rest| / rest over all springs: how far the body is from its rest shape.
double maxStrain(const Springs& s, const VecX& x);

}  // namespace wobble
