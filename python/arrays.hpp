#pragma once
// numpy arguments in and out: checked conversion of inputs (a ValueError naming the call and the argument), and the
// counted views of a World's particle storage.
#include "bindings.hpp"

#include "pbd/detail/real_mass.hpp"
#include "pbd/types.hpp"

#include <pybind11/numpy.h>

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace pbd::python {

/// "(N, 3)"-style text of an array's shape, for messages.
inline std::string shape_text(const py::array& a) {
  std::string s = "(";
  for (py::ssize_t d = 0; d < a.ndim(); ++d) s += (d ? ", " : "") + std::to_string(a.shape(d));
  return s + (a.ndim() == 1 ? ",)" : ")");
}

/// `obj` as a numpy array of numbers of one of the kinds in `kinds` ('f', 'i', 'u'), else a ValueError.
inline py::array numeric_array(py::handle obj, const std::string& what, const char* kinds) {
  py::array a = py::array::ensure(obj);
  if (!a) throw py::value_error(what + " must be an array of numbers");
  const char kind = a.dtype().kind();
  if (std::string(kinds).find(kind) == std::string::npos)
    throw py::value_error(what + " must be an array of " + (std::string(kinds) == "iu" ? "integers" : "real numbers") +
                          ", got dtype " + std::string(py::str(a.dtype())));
  return a;
}

/// `obj` as a C-contiguous array of Real of shape (rows, cols) (rows < 0: any), or of shape (rows,) when cols is 0.
template <class Real>
py::array_t<Real, py::array::c_style> real_array(py::handle obj, const std::string& what, py::ssize_t cols,
                                                 py::ssize_t rows = -1) {
  py::array a = numeric_array(obj, what, "fiu");
  const bool ok = cols == 0 ? a.ndim() == 1 && (rows < 0 || a.shape(0) == rows)
                            : a.ndim() == 2 && a.shape(1) == cols && (rows < 0 || a.shape(0) == rows);
  if (!ok) {
    const std::string n = rows < 0 ? "N" : std::to_string(rows);
    throw py::value_error(what + " must have shape " + (cols == 0 ? "(" + n + ",)" : "(" + n + ", " + std::to_string(cols) + ")") +
                          ", got " + shape_text(a));
  }
  return py::array_t<Real, py::array::c_style | py::array::forcecast>::ensure(a);
}

/// A mass in kg from Python (a double) as Real, for particle `index` of call `fn` (detail::real_mass: 1e39 in float
/// is a pbd::Error, not a pinned particle).
template <class Real> Real mass_arg(double mass, const char* fn, std::size_t index) {
  return detail::real_mass<Real>(mass, fn, index);
}

/// Masses (N,) in kg as Real, each as mass_arg converts it; particles numbered from `first`.
template <class Real> VectorX<Real> masses_arg(py::handle obj, const char* fn, py::ssize_t n, std::size_t first) {
  const auto m = real_array<double>(obj, std::string(fn) + ": masses", 0, n);
  VectorX<Real> out(m.shape(0));
  for (py::ssize_t i = 0; i < m.shape(0); ++i) out[i] = mass_arg<Real>(m.at(i), fn, first + std::size_t(i));
  return out;
}

/// A 3-vector from any sequence or array of 3 numbers.
template <class Real> Vec3<Real> vec3(py::handle obj, const std::string& what) {
  const auto a = real_array<Real>(obj, what, 0, 3);
  return {a.at(0), a.at(1), a.at(2)};
}

/// A particle index from a Python int (a ValueError when negative or beyond 32 bits).
inline Index index_arg(std::int64_t i, const std::string& what) {
  if (i < 0 || i > std::int64_t(UINT32_MAX)) throw py::value_error(what + " must be a particle index >= 0, got " + std::to_string(i));
  return Index(i);
}

/// An (M, 3) array of particle indices as triangles.
inline std::vector<std::array<Index, 3>> triangles_arg(py::handle obj, const std::string& what) {
  py::array a = numeric_array(obj, what, "iu");
  if (a.ndim() != 2 || a.shape(1) != 3) throw py::value_error(what + " must have shape (M, 3), got " + shape_text(a));
  const auto t = py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>::ensure(a);
  std::vector<std::array<Index, 3>> out(std::size_t(t.shape(0)));
  const std::int64_t* p = t.data();
  for (std::size_t i = 0; i < out.size(); ++i)
    for (int k = 0; k < 3; ++k) out[i][k] = index_arg(p[3 * i + k], what + "[" + std::to_string(i) + "]");
  return out;
}

/// What a view of a World's storage holds: the World (kept alive) and its count of live views.
struct ViewToken {
  py::object world;  // the Python World: outlives every view of it
  int* live;         // the World's count of live views (read and written with the GIL held)
};

/// An (n, 3) numpy array viewing `data` (3×n column-major), writeable, counted in *live until it is deleted.
template <class Real> py::array counted_view(py::object world, int* live, Real* data, py::ssize_t n) {
  py::capsule base(new ViewToken{std::move(world), live}, [](void* p) {
    auto* token = static_cast<ViewToken*>(p);
    --*token->live;
    delete token;  // may delete the World last
  });
  ++*live;
  return py::array_t<Real>({n, py::ssize_t(3)}, {py::ssize_t(3 * sizeof(Real)), py::ssize_t(sizeof(Real))}, data, base);
}

}  // namespace pbd::python
