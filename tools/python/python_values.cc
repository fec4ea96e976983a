#include "tools/python/python_values.h"

#include <pybind11/numpy.h>

#include <array>
#include <utility>
#include <vector>

#include "io/surface_reader.h"
#include "measure/input_error.h"

namespace py = pybind11;

namespace surfreg::python {
namespace {

std::string TypeName(const py::handle& value) {
  return py::str(value.get_type().attr("__name__")).cast<std::string>();
}

// The scalar items of `value` (nested lists, tuples and arrays flattened,
// e.g. a 4 x 4 matrix) as text.
void AppendItems(const py::handle& value, const std::string& where, std::vector<std::string>* out) {
  const py::module_ numpy = py::module_::import("numpy");
  if (py::isinstance(value, numpy.attr("ndarray"))) {
    AppendItems(value.attr("ravel")().attr("tolist")(), where, out);
  } else if (py::isinstance<py::list>(value) || py::isinstance<py::tuple>(value)) {
    for (const py::handle item : value) AppendItems(item, where, out);
  } else if (py::isinstance(value, numpy.attr("generic"))) {
    AppendItems(value.attr("item")(), where, out);  // numpy scalars as Python's
  } else if (py::isinstance<py::bool_>(value)) {
    out->push_back(value.cast<bool>() ? "true" : "false");
  } else if (py::isinstance<py::int_>(value)) {
    out->push_back(py::str(value).cast<std::string>());
  } else if (py::isinstance<py::float_>(value)) {
    out->push_back(py::repr(value).cast<std::string>());  // shortest text that reads back exactly
  } else if (IsPath(value)) {
    out->push_back(PathText(value));
  } else {
    throw InputError(where + ": cannot take a value of type " + TypeName(value));
  }
}

}  // namespace

bool IsPath(const py::handle& value) {
  return py::isinstance<py::str>(value) || py::isinstance<py::bytes>(value) ||
         py::isinstance(value, py::module_::import("os").attr("PathLike"));
}

std::string PathText(const py::handle& value) {
  return py::module_::import("os").attr("fsdecode")(value).cast<std::string>();
}

config_value::Value ValueOf(const py::handle& value, const std::string& where) {
  config_value::Value v;
  v.where = where;
  if (value.is_none()) {
    v.kind = config_value::Value::kNull;
    return v;
  }
  std::vector<std::string> items;
  AppendItems(value, where, &items);
  const bool list = py::isinstance<py::list>(value) || py::isinstance<py::tuple>(value) ||
                    py::isinstance(value, py::module_::import("numpy").attr("ndarray"));
  if (list) {
    v.kind = config_value::Value::kList;
    v.items = std::move(items);
  } else {
    v.text = items.front();
  }
  return v;
}

Surface SurfaceFromArray(const py::handle& value, const std::string& name) {
  using Array = py::array_t<double, py::array::c_style | py::array::forcecast>;
  const Array array = Array::ensure(value);
  if (!array) {
    throw InputError(name + ": expected a Surface, a file path or an (N, 3) or (N, 4) array of x, y, z[, "
                     "weight], got " + TypeName(value));
  }
  if (array.ndim() != 2 || (array.shape(1) != 3 && array.shape(1) != 4)) {
    throw InputError(name + ": expected an (N, 3) or (N, 4) array of x, y, z[, weight], got shape " +
                     py::str(py::tuple(array.attr("shape"))).cast<std::string>());
  }
  const auto data = array.unchecked<2>();
  const py::ssize_t n = array.shape(0), columns = array.shape(1);
  std::vector<std::array<double, 3>> points(static_cast<std::size_t>(n));
  std::vector<double> weight;
  if (columns == 4) weight.resize(static_cast<std::size_t>(n));
  for (py::ssize_t i = 0; i < n; ++i) {
    points[i] = {data(i, 0), data(i, 1), data(i, 2)};
    if (columns == 4) weight[i] = data(i, 3);
  }
  Surface surface = MakeSurface(points, std::move(weight), name);
  ValidateSurface(surface);
  return surface;
}

Surface SurfaceOf(const py::handle& value, const std::string& name) {
  if (py::isinstance<Surface>(value)) return value.cast<Surface>();
  if (IsPath(value)) {
    const std::string path = PathText(value);
    py::gil_scoped_release release;
    return ReadSurface(path);
  }
  return SurfaceFromArray(value, name);
}

}  // namespace surfreg::python
