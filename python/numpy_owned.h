// NumPy arrays that own what the library returned (no copy: the vector
// moves into the array's base object), and the columns of libbead's result
// tables as such arrays.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <utility>
#include <vector>

#include "libbead/flow/flow.h"
#include "libbead/profile/bead_geometry.h"
#include "libbead/profile/geometry_row.h"

namespace bead::python {

template <class T>
pybind11::array_t<T> Owned(std::vector<T>&& values, std::vector<pybind11::ssize_t> shape) {
  auto* held = new std::vector<T>(std::move(values));
  pybind11::capsule owner(held, [](void* p) { delete static_cast<std::vector<T>*>(p); });
  return pybind11::array_t<T>(std::move(shape), held->data(), owner);
}

// A block's geometry (bead.measure): [N] arrays.
pybind11::dict GeometryColumns(const std::vector<BeadGeometry>& g);
// A run's geometry rows, the geometry CSV's columns (bead.measure_run).
pybind11::dict RowColumns(const std::vector<GeometryRow>& rows);
// A run's flow, the flow CSV's columns and the total volume (bead.flow).
pybind11::dict FlowColumns(const FlowResult& flow);

}  // namespace bead::python
