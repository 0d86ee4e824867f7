// Text signatures for inspect.signature (signature.hpp says why they are needed).
#include "signature.hpp"

#include <cmath>

namespace pbd::python {

namespace {

/// A default value as inspect can read it back (a literal): inf, which Python prints as `inf`, is written 1e999.
std::string default_text(pybind11::handle value) {
  if (pybind11::isinstance<pybind11::float_>(value)) {
    const double x = value.cast<double>();
    if (std::isinf(x)) return x > 0 ? "1e999" : "-1e999";
  }
  return std::string(pybind11::repr(value));
}

}  // namespace

bool overloads_a_function(const pybind11::detail::function_record& r) {
  PyObject* s = r.sibling.ptr();
  if (s && PyInstanceMethod_Check(s)) s = PyInstanceMethod_GET_FUNCTION(s);
  return s && PyCFunction_Check(s) && r.name && std::string(reinterpret_cast<PyCFunctionObject*>(s)->m_ml->ml_name) == r.name;
}

std::string signed_doc(const pybind11::detail::function_record& r) {
  namespace py = pybind11;
  std::string params;
  auto add = [&](const std::string& p) { params += (params.empty() ? "" : ", ") + p; };
  // With named arguments, r.args lists them all (self first for a method); without, only their count is known
  // (nargs_pos: every argument, as there is no kw_only without names) and pybind11 calls them arg0, arg1, ...
  const std::size_t first = r.is_method ? 1 : 0;
  // "self", not "$self": a pybind11 function is bound to its record (__self__), so inspect would drop a $self from
  // the function and then the first real parameter from the bound method.
  if (r.is_method) add("self");
  if (r.is_method) add("/");  // self: positional only
  if (r.args.empty()) {
    for (std::size_t i = first; i < r.nargs_pos; ++i) add("arg" + std::to_string(i - first));
  } else {
    for (std::size_t i = first; i < r.args.size(); ++i) {
      if (i == r.nargs_pos && r.nargs_pos < r.args.size()) add("*");
      const auto& a = r.args[i];
      std::string p = a.name;
      if (a.descr) p += std::string("=") + a.descr;
      else if (a.value) p += "=" + default_text(a.value);
      add(p);
    }
  }
  return std::string(r.name) + "(" + params + ")\n--\n\n" + (r.doc ? r.doc : "");
}

}  // namespace pbd::python
