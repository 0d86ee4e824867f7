#pragma once
/// \file custom_constraints.hpp
/// User-defined fixed-arity constraint types, projected by the same serial, colored and Jacobi machinery as the
/// built-in ones.
///
/// A host type C needs what the built-in types have (see constraints/stretch.hpp): `static constexpr int kArity`,
/// `static constexpr bool kInequality`, `static constexpr const char* kName`, `std::array<Index, kArity> particles`,
/// `Index set`, optionally `static constexpr bool kUnitGradients = true` when every |∇_i C| is 1, and a free function
/// `bool evaluate(const C&, const Vec3<Real> (&p)[kArity], Real& C,
/// Vec3<Real> (&grad)[kArity])` found by argument-dependent lookup. Each type is stored as its own contiguous array;
/// the only virtual call is one per color range (never per constraint), so a custom type runs the same tight,
/// inlined loop as a built-in one and is just as deterministic.
#include "pbd/colored_constraints.hpp"
#include "pbd/constraints/projection.hpp"

#include <memory>
#include <typeindex>
#include <vector>

namespace pbd {

/// One user-defined constraint type's constraints (type-erased), in insertion and in color order.
template <class Real> class CustomConstraintsBase {
public:
  virtual ~CustomConstraintsBase() = default;
  virtual std::unique_ptr<CustomConstraintsBase> clone() const = 0;  ///< deep copy
  virtual std::type_index type() const = 0;                          ///< the host type C
  virtual const char* name() const = 0;                              ///< C::kName
  virtual std::size_t size() const = 0;                              ///< number of constraints
  virtual bool colored_up_to_date() const = 0;                       ///< color order covers every constraint
  virtual void color(const std::vector<std::uint8_t>& fixed, const coloring::Options& o) = 0;  ///< colors all
  virtual bool color_appended(const std::vector<std::uint8_t>& fixed) = 0;  ///< colors only new ones (false: all)
  virtual Index num_colors() const = 0;                                     ///< colors of the color order
  virtual Index color_begin(Index c) const = 0;                             ///< first constraint of color c
  virtual void count_particles(std::vector<Index>& count) const = 0;  ///< adds 1 per constraint at each particle
  virtual std::size_t erase_touching(Index particle) = 0;  ///< removes every constraint on `particle`; returns how many
  virtual void reset_lambda() = 0;                                    ///< sets every λ to 0 (both orders)
  /// Gauss-Seidel over all constraints in insertion order (serial reference).
  virtual void project_serial(Real* p, const Real* w, const SolveCoefficients<Real>* coeff) = 0;
  /// Gauss-Seidel over color-order constraints [b, e) (inside one color).
  virtual void project_colored(Index b, Index e, Real* p, const Real* w, const SolveCoefficients<Real>* coeff) = 0;
  /// Jacobi: adds the corrections of color-order constraints [b, e) to delta (3 per particle).
  virtual void accumulate_colored(Index b, Index e, const Real* p, const Real* w, const SolveCoefficients<Real>* coeff,
                                  Real* delta) = 0;
};

/// The constraints of host type C.
template <class C, class Real> class CustomConstraints final : public CustomConstraintsBase<Real> {
public:
  std::vector<C> items;        ///< insertion order
  ColoredArray<C> colored;     ///< color order
  std::vector<Real> lambda;    ///< λ in insertion order (serial solver)
  std::vector<Real> lambda_c;  ///< λ in color order (colored and Jacobi solvers)

  std::unique_ptr<CustomConstraintsBase<Real>> clone() const override { return std::make_unique<CustomConstraints>(*this); }
  std::type_index type() const override { return typeid(C); }
  const char* name() const override { return C::kName; }
  std::size_t size() const override { return items.size(); }
  bool colored_up_to_date() const override { return colored.color.size() == items.size(); }
  void color(const std::vector<std::uint8_t>& fixed, const coloring::Options& o) override {
    colored = color_array(items, fixed, o);
  }
  bool color_appended(const std::vector<std::uint8_t>& fixed) override {
    return pbd::color_appended(colored, items, fixed);
  }
  Index num_colors() const override { return colored.num_colors(); }
  Index color_begin(Index c) const override { return colored.offsets[c]; }
  void count_particles(std::vector<Index>& count) const override {
    for (const C& c : items)
      for (Index p : c.particles) ++count[p];
  }
  std::size_t erase_touching(Index particle) override {
    const std::size_t before = items.size();
    std::erase_if(items, [&](const C& c) {
      for (Index p : c.particles)
        if (p == particle) return true;
      return false;
    });
    if (items.size() != before) colored = {};
    return before - items.size();
  }
  void reset_lambda() override {
    lambda.assign(items.size(), Real(0));
    lambda_c.assign(items.size(), Real(0));
  }
  void project_serial(Real* p, const Real* w, const SolveCoefficients<Real>* coeff) override {
    for (std::size_t i = 0; i < items.size(); ++i) project(items[i], p, w, coeff[items[i].set], lambda[i]);
  }
  void project_colored(Index b, Index e, Real* p, const Real* w, const SolveCoefficients<Real>* coeff) override {
    for (Index i = b; i < e; ++i) project(colored.items[i], p, w, coeff[colored.items[i].set], lambda_c[i]);
  }
  void accumulate_colored(Index b, Index e, const Real* p, const Real* w, const SolveCoefficients<Real>* coeff,
                          Real* delta) override {
    for (Index i = b; i < e; ++i) accumulate(colored.items[i], p, w, coeff[colored.items[i].set], lambda_c[i], delta);
  }
};

/// All user-defined constraint types of a world; copying deep-copies them.
template <class Real> class CustomTypes {
public:
  CustomTypes() = default;
  CustomTypes(const CustomTypes& o) { *this = o; }  ///< deep copy
  CustomTypes& operator=(const CustomTypes& o) {   ///< deep copy
    if (this != &o) {
      types_.clear();
      for (const auto& t : o.types_) types_.push_back(t->clone());
    }
    return *this;
  }
  CustomTypes(CustomTypes&&) noexcept = default;             ///< move
  CustomTypes& operator=(CustomTypes&&) noexcept = default;  ///< move

  /// The storage of type C, created on first use.
  template <class C> CustomConstraints<C, Real>& of() {
    for (auto& t : types_)
      if (t->type() == typeid(C)) return static_cast<CustomConstraints<C, Real>&>(*t);
    types_.push_back(std::make_unique<CustomConstraints<C, Real>>());
    return static_cast<CustomConstraints<C, Real>&>(*types_.back());
  }
  /// The storage of type C, or nullptr if none was added.
  template <class C> const CustomConstraints<C, Real>* find() const {
    for (const auto& t : types_)
      if (t->type() == typeid(C)) return static_cast<const CustomConstraints<C, Real>*>(t.get());
    return nullptr;
  }
  /// Every type, in the order they were first added (their solver order).
  const std::vector<std::unique_ptr<CustomConstraintsBase<Real>>>& types() const { return types_; }
  bool empty() const { return types_.empty(); }  ///< true when the world has no user-defined constraints

private:
  std::vector<std::unique_ptr<CustomConstraintsBase<Real>>> types_;
};

}  // namespace pbd
