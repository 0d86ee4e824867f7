#pragma once
// Readable reprs of the parameter and result classes: "pbd.Name(field=value, ...)" with each value as Python prints
// it (shortest round-trip floats, True/False, lists), so that a printed StepParams or StepStats shows every field.
#include "bindings.hpp"

#include <initializer_list>
#include <string>
#include <utility>

namespace pbd::python {

/// Python's repr of a C++ value (through its pybind11 conversion).
template <class T> std::string py_repr(const T& value) { return std::string(py::repr(py::cast(value))); }

/// "pbd.<enum value>" for a bound enum value, e.g. pbd.Solver.colored.
template <class E> std::string enum_repr(E value) { return "pbd." + std::string(py::str(py::cast(value))); }

/// "pbd.<name>(f1=v1, f2=v2, ...)" of already formatted values.
inline std::string fields_repr(const std::string& name, std::initializer_list<std::pair<const char*, std::string>> fields) {
  std::string out = "pbd." + name + "(";
  bool first = true;
  for (const auto& [field, value] : fields) {
    out += (first ? "" : ", ") + std::string(field) + "=" + value;
    first = false;
  }
  return out + ")";
}

}  // namespace pbd::python
