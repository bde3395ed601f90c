/// \file enum_binding.hpp
/// Binds a C++ enum whose values run 0 .. last and that has a ToString(): each Python
/// value is named after ToString() in upper case with '-' -> '_' ("line-search-failure"
/// becomes LINE_SEARCH_FAILURE), so a value added in C++ needs only its `last` updated.
#pragma once

#include <pybind11/pybind11.h>

#include <algorithm>
#include <cctype>
#include <string>

namespace bindings {

template <typename Enum>
pybind11::enum_<Enum> BindEnum(pybind11::module_& m, const char* name, Enum last,
                               const char* doc) {
  pybind11::enum_<Enum> e(m, name, doc);
  for (int v = 0; v <= static_cast<int>(last); ++v) {
    std::string label = ToString(static_cast<Enum>(v));
    std::transform(label.begin(), label.end(), label.begin(), [](unsigned char c) {
      return c == '-' ? '_' : static_cast<char>(std::toupper(c));
    });
    e.value(label.c_str(), static_cast<Enum>(v));
  }
  // The C++ spelling ("min", "fb", "penalized-fb") for messages and string arguments.
  e.def_property_readonly("label", [](Enum v) { return std::string(ToString(v)); });
  return e;
}

}  // namespace bindings
