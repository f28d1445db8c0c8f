// The parts of the frepcore module defined in their own translation units.
#pragma once

#include <pybind11/pybind11.h>

namespace frep {

void bindHSpline(pybind11::module_& m);  // hspline_bindings.cpp

}  // namespace frep
