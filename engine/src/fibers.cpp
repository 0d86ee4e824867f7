// The plastic flow, breaks and readings of the constraints that follow a curve (fibers.hpp).
#include "fibers.hpp"

#include <cmath>
#include <limits>

namespace pbd::detail {
namespace {

// The force λ says constraint c of type C (at stored position i) carries, over its scale, or NaN
// (FiberReading::force).
template <class C, class Real> double force_of(const Model<Real>& m, const State<Real>& s, const C& c, Index i) {
  constexpr std::size_t kType = TypeIndex<C, BuiltinConstraintTypes<Real>>::value;
  const Stiffness& st = m.sets[c.set];
  const bool kept = st.mode == StiffnessMode::material || (st.mode == StiffnessMode::xpbd && st.compliance != 0.0);
  // (by pointer: a conditional between the store's λ and an empty vector would copy all of them each call)
  const std::vector<Real>* lam = kType < s.lambda.size() ? &s.lambda[kType] : nullptr;
  if (!kept || !(s.lambda_h2 > 0.0) || !lam || std::size_t(i) >= lam->size())
    return std::numeric_limits<double>::quiet_NaN();
  return -double((*lam)[i]) / (s.lambda_h2 * material_scale(c));
}

// Calls f(store, type index) for each store of a material type.
template <class Stores, class F> void for_each_material_store(Stores& stores, F&& f) {
  for_each_store(stores, [&](auto& st, auto type) {
    using C = typename std::decay_t<decltype(st)>::value_type;
    if constexpr (takes_material<C>()) f(st, type);
  });
}

// Whether some constraint of a material type is in a set whose curve reaches `strain` (a member of Material).
template <class Real> bool some_curve_reaches(const Model<Real>& m, double Material::*strain) {
  bool any_constraint = false;
  for_each_material_store(m.stores, [&](const auto& st, auto) { any_constraint = any_constraint || !st.empty(); });
  if (!any_constraint) return false;
  for (const Stiffness& s : m.sets)
    if (s.mode == StiffnessMode::material && s.material.*strain < Material::kNever) return true;
  return false;
}

}  // namespace

template <class Real> bool fibers_flow(const Model<Real>& m) { return some_curve_reaches(m, &Material::yield_strain); }
template <class Real> bool fibers_break(const Model<Real>& m) { return some_curve_reaches(m, &Material::rupture_strain); }

template <class Real> void flow_fibers(Model<Real>& m, const Real* p) {
  for_each_material_store(m.stores, [&](auto& st, auto) {
    for (auto& c : st.items) {
      const Material* curve_of = m.sets[c.set].curve();
      if (!curve_of) continue;
      c.plastic = Real(curve_of->plastic_after(material_strain(c, p), double(c.plastic)));
    }
  });
}

template <class Real> std::vector<FiberBreak> find_breaks(const Model<Real>& m, const State<Real>& s, std::int64_t step) {
  std::vector<FiberBreak> out;
  const Real* x = s.x.data();
  for_each_material_store(m.stores, [&](const auto& st, auto) {
    using C = typename std::decay_t<decltype(st)>::value_type;
    for (Index u = 0; u < Index(st.size()); ++u) {
      const C& c = st.at(u);
      const Material* curve_of = m.sets[c.set].curve();
      if (!curve_of || !(curve_of->rupture_strain < Material::kNever)) continue;
      const double strain = material_strain(c, x);
      if (!(strain >= curve_of->rupture_strain)) continue;
      FiberBreak b{step, s.time, C::kName, u, c.set, {}, C::kArity, strain, double(c.plastic),
                   force_of(m, s, c, st.stored(u))};
      for (int i = 0; i < C::kArity; ++i) b.particles[std::size_t(i)] = c.particles[std::size_t(i)];
      out.push_back(b);
    }
  });
  return out;
}

template <class C, class Real> std::vector<FiberReading> read_fibers(const Model<Real>& m, const State<Real>& s) {
  const auto& st = m.template store<C>();
  std::vector<FiberReading> out(st.size());
  for (Index u = 0; u < Index(st.size()); ++u) {
    const C& c = st.at(u);
    out[u] = {material_strain(c, s.x.data()), double(c.plastic), force_of(m, s, c, st.stored(u))};
  }
  return out;
}

template <class Real> PlasticRollback<Real>::PlasticRollback(const Model<Real>& m, bool keep) : kept_(keep) {
  if (!keep) return;
  plastic_.resize(kNumBuiltinTypes);
  for_each_material_store(m.stores, [&](const auto& st, auto type) {
    for (const auto& c : st.items) plastic_[decltype(type)::value].push_back(c.plastic);
  });
}

template <class Real> void PlasticRollback<Real>::restore(Model<Real>& m) {
  if (!kept_) return;
  for_each_material_store(m.stores, [&](auto& st, auto type) {
    const std::vector<Real>& kept = plastic_[decltype(type)::value];
    for (std::size_t i = 0; i < st.items.size(); ++i) st.items[i].plastic = kept[i];
  });
}

#define PBD_FIBERS_INSTANTIATE(Real)                                                                        \
  template bool fibers_flow(const Model<Real>&);                                                            \
  template bool fibers_break(const Model<Real>&);                                                           \
  template void flow_fibers(Model<Real>&, const Real*);                                                     \
  template std::vector<FiberBreak> find_breaks(const Model<Real>&, const State<Real>&, std::int64_t);       \
  template std::vector<FiberReading> read_fibers<FiberConstraint<Real>>(const Model<Real>&, const State<Real>&); \
  template std::vector<FiberReading> read_fibers<TetFiberConstraint<Real>>(const Model<Real>&, const State<Real>&); \
  template class PlasticRollback<Real>;

PBD_FIBERS_INSTANTIATE(float)
PBD_FIBERS_INSTANTIATE(double)
#undef PBD_FIBERS_INSTANTIATE

}  // namespace pbd::detail
