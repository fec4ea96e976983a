#pragma once
// Python values as the libraries take them: keyword arguments as key values
// (measure/option_keys.h, so a keyword gets the messages a config key gets,
// "keyword 'cost' expects one of auto, volume, axial, axial_sparser, got 'fast'"), and surfaces
// given as a file path, a Surface or an (N, 3) / (N, 4) array.
#include <pybind11/pybind11.h>

#include <string>

#include "measure/option_keys.h"
#include "measure/surface.h"

namespace surfreg::python {

// A str, bytes or os.PathLike.
bool IsPath(const pybind11::handle& value);
std::string PathText(const pybind11::handle& value);

// `value` as a key's value: None as nothing, a list, tuple or array
// (flattened) as a list, a bool, number or path as its text; `where`
// ("keyword 'cost'") starts its messages.
config_value::Value ValueOf(const pybind11::handle& value, const std::string& where);

// An (N, 3) / (N, 4) array of x, y, z[, weight] as a Surface named `name`,
// checked as a file's samples are (InputError naming `name`).
Surface SurfaceFromArray(const pybind11::handle& value, const std::string& name);

// A surface argument: a Surface (copied), a file path (read with `classes`
// and `columns` as ReadOptions), or an array. `name` names an array.
Surface SurfaceOf(const pybind11::handle& value, const std::string& name);

}  // namespace surfreg::python
