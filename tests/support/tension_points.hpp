#pragma once
// The strains a tension test reads a curve at (tests/engine/fiber_test.cpp, tet_fiber_test.cpp): 20 across the
// three parts of a Material's curve, 6 in the toe, 7 on the linear part and 7 past yield, none at a part's ends.
#include "pbd/material.hpp"

#include <vector>

namespace pbd::test {

inline std::vector<double> tension_points(const Material& m) {
  std::vector<double> s;
  for (int i = 0; i < 6; ++i) s.push_back(m.toe_strain * (0.3 + 0.14 * i));
  for (int i = 0; i < 7; ++i) s.push_back(m.toe_strain + (m.yield_strain - m.toe_strain) * (0.1 + 0.13 * i));
  for (int i = 0; i < 7; ++i) s.push_back(m.yield_strain + (m.rupture_strain - m.yield_strain) * (0.05 + 0.13 * i));
  return s;
}

}  // namespace pbd::test
