// The Python module `surfreg`: measure(), merge() and align(), the CLI's
// `measure --json`, `merge` and `align --json` as dicts. Both run the CLI's own code
// (tools/measure_run.h, tools/align_run.h) and parse its JSON document, so
// keys and values are the CLI's by construction; only "matrix" becomes a
// 4 x 4 numpy array.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <array>
#include <cstdio>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "measure/input_error.h"
#include "measure/surface.h"
#include "tools/align_config.h"
#include "tools/align_run.h"
#include "tools/measure_parts.h"
#include "tools/measure_run.h"
#include "tools/measure_tiled.h"

namespace py = pybind11;

namespace surfreg {
namespace {

bool IsPath(const py::handle& value) {
  return py::isinstance<py::str>(value) || py::isinstance<py::bytes>(value) ||
         py::isinstance(value, py::module_::import("os").attr("PathLike"));
}

std::string PathText(const py::handle& value) {
  return py::module_::import("os").attr("fsdecode")(value).cast<std::string>();
}

// Appends the scalar items of `value` (nested lists, tuples and arrays
// flattened, e.g. a 4 x 4 known_matrix) as a flag holds them.
void AppendItems(const py::handle& value, const std::string& where, std::vector<std::string>* out) {
  const py::module_ numpy = py::module_::import("numpy");
  if (py::isinstance(value, numpy.attr("ndarray"))) {
    AppendItems(value.attr("ravel")().attr("tolist")(), where, out);
  } else if (py::isinstance<py::list>(value) || py::isinstance<py::tuple>(value)) {
    for (const py::handle item : value) AppendItems(item, where, out);
  } else if (py::isinstance(value, numpy.attr("generic"))) {
    AppendItems(value.attr("item")(), where, out);  // numpy scalars as Python's
  } else if (value.is_none()) {
    out->push_back("");  // a file key: no file; any other key rejects it
  } else if (py::isinstance<py::bool_>(value)) {
    out->push_back(value.cast<bool>() ? "true" : "false");
  } else if (py::isinstance<py::int_>(value)) {
    out->push_back(py::str(value).cast<std::string>());
  } else if (py::isinstance<py::float_>(value)) {
    out->push_back(py::repr(value).cast<std::string>());  // shortest text that reads back exactly
  } else if (IsPath(value)) {
    out->push_back(PathText(value));
  } else {
    throw InputError(where + ": cannot take a value of type " +
                     py::str(value.get_type().attr("__name__")).cast<std::string>());
  }
}

// Keyword arguments as the CLI's settings: "keyword 'cost'" starts their
// messages where the CLI's say "flag '--cost'".
std::vector<Setting> Settings(const py::kwargs& kwargs) {
  std::vector<Setting> settings;
  for (const auto& [name, value] : kwargs) {
    Setting s;
    s.key = py::str(name).cast<std::string>();
    s.where = "keyword '" + s.key + "'";
    std::vector<std::string> items;
    AppendItems(value, s.where, &items);
    const bool list = py::isinstance<py::list>(value) || py::isinstance<py::tuple>(value) ||
                      py::isinstance(value, py::module_::import("numpy").attr("ndarray"));
    if (list) {
      for (std::size_t i = 0; i < items.size(); ++i) s.value += (i ? ", " : "") + items[i];
      s.value = "[" + s.value + "]";
    } else {
      s.value = items.front();
    }
    settings.push_back(std::move(s));
  }
  return settings;
}

// A file path (str, bytes, os.PathLike), or an (N, 3) / (N, 4) array of x,
// y, z[, weight] copied into a Surface (checked as a file's samples are),
// named `name` in messages and in the result.
SurfaceInput ToSurface(const py::object& value, const std::string& name) {
  if (IsPath(value)) return {PathText(value), std::nullopt};
  using Array = py::array_t<double, py::array::c_style | py::array::forcecast>;
  const Array array = Array::ensure(value);
  if (!array) {
    throw InputError(name + ": expected a file path or an (N, 3) or (N, 4) array of x, y, z[, "
                     "weight], got " + py::str(value.get_type().attr("__name__")).cast<std::string>());
  }
  const std::string shape = py::str(py::tuple(array.attr("shape"))).cast<std::string>();
  if (array.ndim() != 2 || (array.shape(1) != 3 && array.shape(1) != 4)) {
    throw InputError(name + ": expected an (N, 3) or (N, 4) array of x, y, z[, weight], got shape " +
                     shape);
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
  return {name, std::move(surface)};
}

// The CLI's JSON document as a dict; "matrix" as a 4 x 4 float64 array.
py::dict ToDict(const std::string& json) {
  py::dict result = py::module_::import("json").attr("loads")(json);
  if (result.contains("matrix")) {
    result["matrix"] = py::module_::import("numpy").attr("array")(result["matrix"], "float64");
  }
  return result;
}

// shard="K/N", partial="P.json", resume=True: a tiled measure in parts, as
// the CLI's --shard, --partial and --resume (tools/measure_tiled.h).
TiledParts PartsOf(py::kwargs* kwargs) {
  std::string shard, partial;
  bool resume = false;
  auto take = [kwargs](const char* key) {
    py::object value = py::none();
    if (kwargs->contains(key)) value = kwargs->attr("pop")(key);
    return value;
  };
  const py::object s = take("shard"), p = take("partial"), r = take("resume");
  if (!s.is_none()) shard = py::str(s).cast<std::string>();
  if (!p.is_none()) {
    if (!IsPath(p)) throw InputError("keyword 'partial': expected a file path");
    partial = PathText(p);
  }
  if (!r.is_none()) {
    if (!py::isinstance<py::bool_>(r)) throw InputError("keyword 'resume': expected True or False");
    resume = r.cast<bool>();
  }
  return TiledPartsOf(shard, partial, resume, [](const std::string& key) { return "keyword '" + key + "'"; },
                      "partial='P.json'");
}

py::object MeasurePy(const py::object& a, const py::object& b, py::kwargs kwargs) {
  const TiledParts parts = PartsOf(&kwargs);
  const std::vector<Setting> settings = Settings(kwargs);
  SurfaceInput sa = ToSurface(a, "array A"), sb = ToSurface(b, "array B");
  std::string json;
  {
    py::gil_scoped_release release;  // the inputs are C++ copies by now
    const MeasureReport report = MeasureSurfaces(std::move(sa), std::move(sb), settings, nullptr, &parts);
    if (parts.shards > 1) return py::none();  // the shard's result is its partial file
    json = MeasureJson(report);
  }
  return ToDict(json);
}

py::dict MergePy(const py::object& out, const py::list& parts, const py::object& dod) {
  std::vector<std::string> args;
  if (!IsPath(out)) throw InputError("argument out: expected a file path");
  args.push_back(PathText(out));
  for (const py::handle part : parts) {
    if (!IsPath(part)) throw InputError("argument parts: expected file paths");
    args.push_back(PathText(part));
  }
  if (args.size() < 2) throw InputError("argument parts: no parts to merge");
  const std::string dod_path = dod.is_none() ? std::string() : PathText(dod);
  {
    py::gil_scoped_release release;
    MergeMeasureParts(args, dod_path, false, [](const MeasureReport&) {});
  }
  return ToDict(py::module_::import("pathlib").attr("Path")(args[0]).attr("read_text")().cast<std::string>());
}

py::dict AlignPy(const py::object& reference, const py::object& moving, const py::kwargs& kwargs) {
  const std::vector<Setting> settings = Settings(kwargs);
  SurfaceInput r = ToSurface(reference, "array reference");
  SurfaceInput m = ToSurface(moving, "array moving");
  AlignConfig config;
  ApplyAlignArguments(r.name, m.name, &config);
  for (const Setting& s : settings) ApplyAlignSetting(s.key, s.value, s.where, &config);
  FinishAlignConfig(&config);
  const bool progress = config.progress;
  const int levels = config.options.levels;
  std::string json;
  {
    py::gil_scoped_release release;  // the inputs are C++ copies by now
    json = AlignSurfaces(std::move(config), std::move(r.samples), std::move(m.samples),
                         [progress, levels](const AlignOptions::Iteration& it) {
                           if (progress) std::fputs(AlignProgressLine(it, levels).c_str(), stderr);
                         })
               .json;
  }
  return ToDict(json);
}

}  // namespace
}  // namespace surfreg

PYBIND11_MODULE(surfreg, m) {
  m.doc() = "surfreg: the volume between two height-field surfaces, and their rigid alignment";
  m.attr("__version__") = SURFREG_VERSION;
  // Bad input: a ValueError (this subclass) with the CLI's one-line message.
  py::register_exception<surfreg::InputError>(m, "InputError", PyExc_ValueError);
  m.def("measure", &surfreg::MeasurePy, py::arg("a"), py::arg("b"),
        "measure(a, b, **options) -> dict\n\n"
        "`surfreg measure A B --json` as a dict: B against A. A surface is a file path or an\n"
        "(N, 3) / (N, 4) float64 array of x, y, z[, weight]; options are measure's flags\n"
        "(volume, weights, domain, lod, reference_crs, ...) as keywords. Tiled DEMs (tile,\n"
        "max_memory) also take shard='K/N' with partial='P.json' (returns None: join the\n"
        "parts with merge()) and resume=True (go on after a killed run).");
  m.def("merge", &surfreg::MergePy, py::arg("out"), py::arg("parts"), py::arg("dod") = py::none(),
        "merge(out, parts, dod=None) -> dict\n\n"
        "`surfreg merge OUT.json P1.json ...`: the partials of a sharded tiled measure joined\n"
        "into the unsharded result, written to `out` and returned as measure() returns it;\n"
        "with dod, the shards' DoD bands joined into that GeoTIFF.");
  m.def("align", &surfreg::AlignPy, py::arg("reference"), py::arg("moving"),
        "align(reference, moving, **options) -> dict\n\n"
        "`surfreg align REFERENCE MOVING --json` as a dict: the rigid motion of moving onto\n"
        "reference (\"matrix\": 4 x 4 numpy array, moving -> reference, input coordinates),\n"
        "the measures before and after, the verdict. Options are align's config keys\n"
        "(cost, free, max_iterations, output, ...) as keywords.");
}
