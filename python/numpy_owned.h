// NumPy arrays that own what the library returned (no copy: the vector
// moves into the array's base object), and the columns of libbead's result
// tables as such arrays.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <string>
#include <utility>
#include <vector>

#include "libbead/core/error.h"
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

// A 1-D array of numbers given to a function (converted once when it is not
// float64 and C-contiguous), as a vector; `function` and `name` say which
// argument in the error when it is not 1-D.
using InputVector = pybind11::array_t<double, pybind11::array::c_style | pybind11::array::forcecast>;
inline std::vector<double> ToVector(const InputVector& a, const char* function, const char* name) {
  if (a.ndim() != 1) throw Error(std::string(function) + ": " + name + " must be 1-D");
  return std::vector<double>(a.data(), a.data() + a.shape(0));
}

// One column: f(item) for every item, as an owning [N] array.
template <class T, class Items, class F>
pybind11::array_t<T> Column(const Items& items, F f) {
  std::vector<T> v;
  v.reserve(items.size());
  for (const auto& item : items) v.push_back(static_cast<T>(f(item)));
  return Owned(std::move(v), {static_cast<pybind11::ssize_t>(v.size())});
}

// A yes/no column (std::vector<bool> holds no array to hand over: filled in place).
template <class Items, class F>
pybind11::array_t<bool> Flags(const Items& items, F f) {
  pybind11::array_t<bool> out(static_cast<pybind11::ssize_t>(items.size()));
  auto m = out.mutable_unchecked<1>();
  pybind11::ssize_t i = 0;
  for (const auto& item : items) m(i++) = f(item);
  return out;
}

// A block's geometry (bead.measure): [N] arrays.
pybind11::dict GeometryColumns(const std::vector<BeadGeometry>& g);
// A run's geometry rows, the geometry CSV's columns (bead.measure_run).
pybind11::dict RowColumns(const std::vector<GeometryRow>& rows);
// A run's flow, the flow CSV's columns and the total volume (bead.flow).
pybind11::dict FlowColumns(const FlowResult& flow);

}  // namespace bead::python
