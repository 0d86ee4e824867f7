#pragma once
// Signatures that inspect.signature can read. CPython gives a builtin function a signature from a docstring that
// begins "name(params)\n--\n\n" (its __text_signature__); pybind11's own first line "name(a: T) -> R" is not in that
// form, so the module turns pybind11's signatures off (module.cpp) and every def ends with the `sig` attribute, which
// puts the text signature made from the def's own py::arg list in front of its docstring. The parameters' types are
// in python/pbd.pyi; tests/python/test_stubs.py checks that the stubs and these signatures name the same parameters
// with the same defaults.
#include <pybind11/pybind11.h>

#include <deque>
#include <string>

namespace pbd::python {

/// Marks a def for a text signature; give it as the def's last attribute (after its py::arg list and docstring).
struct TextSignature {};
inline constexpr TextSignature sig{};

/// Whether `r` is a further overload of a function of its name already defined (its sibling).
bool overloads_a_function(const pybind11::detail::function_record& r);

/// The docstring of `r` with its text signature in front, e.g. "step(self, /, forces=None)\n--\n\n<doc>".
std::string signed_doc(const pybind11::detail::function_record& r);

}  // namespace pbd::python

namespace pybind11::detail {
template <> struct process_attribute<pbd::python::TextSignature> : process_attribute_default<pbd::python::TextSignature> {
  static void init(const pbd::python::TextSignature&, function_record* r) {
    // A second overload of a name (the same call on World and WorldDouble) adds nothing: pybind11 would append its
    // docstring, signature and all, to the first one's.
    if (pbd::python::overloads_a_function(*r)) {
      r->doc = const_cast<char*>("");
      return;
    }
    // pybind11 copies the docstring when the def completes; until then it must outlive this call.
    static std::deque<std::string> docs;
    docs.push_back(pbd::python::signed_doc(*r));
    r->doc = const_cast<char*>(docs.back().c_str());
  }
};
}  // namespace pybind11::detail
