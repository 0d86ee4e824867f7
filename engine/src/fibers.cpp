// The fibers' plastic flow, breaks and readings (fibers.hpp).
#include "fibers.hpp"

#include <cmath>
#include <limits>

namespace pbd::detail {
namespace {

constexpr std::size_t kFiber = TypeIndex<FiberConstraint<float>, BuiltinConstraintTypes<float>>::value;

template <class Real> const Store<FiberConstraint<Real>>& fibers_of(const Model<Real>& m) {
  return m.template store<FiberConstraint<Real>>();
}

// Total strain of fiber c at positions x (3 per particle).
template <class Real> double strain_of(const FiberConstraint<Real>& c, const Real* x) {
  const Real* a = x + 3 * std::size_t(c.particles[0]);
  const Real* b = x + 3 * std::size_t(c.particles[1]);
  const double dx = double(a[0]) - double(b[0]), dy = double(a[1]) - double(b[1]), dz = double(a[2]) - double(b[2]);
  return std::sqrt(dx * dx + dy * dy + dz * dz) / double(c.rest) - 1.0;
}

// The tension λ says fiber c (at stored position i) carries, or NaN (FiberReading::force).
template <class Real> double force_of(const Model<Real>& m, const State<Real>& s, const FiberConstraint<Real>& c, Index i) {
  const Stiffness& st = m.sets[c.set];
  const bool kept = st.mode == StiffnessMode::material || (st.mode == StiffnessMode::xpbd && st.compliance != 0.0);
  // (by pointer: a conditional between the store's λ and an empty vector would copy all of them each call)
  const std::vector<Real>* lam = kFiber < s.lambda.size() ? &s.lambda[kFiber] : nullptr;
  if (!kept || !(s.lambda_h2 > 0.0) || !lam || std::size_t(i) >= lam->size())
    return std::numeric_limits<double>::quiet_NaN();
  return -double((*lam)[i]) / s.lambda_h2;
}

}  // namespace

template <class Real> bool fibers_flow(const Model<Real>& m) {
  if (fibers_of(m).empty()) return false;
  for (const Stiffness& s : m.sets)
    if (s.mode == StiffnessMode::material && s.material.yield_strain < Material::kNever) return true;
  return false;
}

template <class Real> void flow_fibers(Model<Real>& m, const Real* p) {
  for (FiberConstraint<Real>& c : m.template store<FiberConstraint<Real>>().items) {
    const Material* curve_of = m.sets[c.set].curve();
    if (!curve_of) continue;
    c.plastic = Real(curve_of->plastic_after(strain_of(c, p), double(c.plastic)));
  }
}

template <class Real> std::vector<FiberBreak> find_breaks(const Model<Real>& m, const State<Real>& s, std::int64_t step) {
  std::vector<FiberBreak> out;
  const auto& st = fibers_of(m);
  const Real* x = s.x.data();
  for (Index u = 0; u < Index(st.size()); ++u) {
    const FiberConstraint<Real>& c = st.at(u);
    const Material* curve_of = m.sets[c.set].curve();
    if (!curve_of || !(curve_of->rupture_strain < Material::kNever)) continue;
    const double strain = strain_of(c, x);
    if (!(strain >= curve_of->rupture_strain)) continue;
    out.push_back({step, s.time, u, c.set, c.particles[0], c.particles[1], strain, force_of(m, s, c, st.stored(u))});
  }
  return out;
}

template <class Real> std::vector<FiberReading> read_fibers(const Model<Real>& m, const State<Real>& s) {
  const auto& st = fibers_of(m);
  std::vector<FiberReading> out(st.size());
  for (Index u = 0; u < Index(st.size()); ++u) {
    const FiberConstraint<Real>& c = st.at(u);
    out[u] = {strain_of(c, s.x.data()), double(c.plastic), force_of(m, s, c, st.stored(u))};
  }
  return out;
}

#define PBD_FIBERS_INSTANTIATE(Real)                                                                        \
  template bool fibers_flow(const Model<Real>&);                                                            \
  template void flow_fibers(Model<Real>&, const Real*);                                                     \
  template std::vector<FiberBreak> find_breaks(const Model<Real>&, const State<Real>&, std::int64_t);       \
  template std::vector<FiberReading> read_fibers(const Model<Real>&, const State<Real>&);

PBD_FIBERS_INSTANTIATE(float)
PBD_FIBERS_INSTANTIATE(double)
#undef PBD_FIBERS_INSTANTIATE

}  // namespace pbd::detail
