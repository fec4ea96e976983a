// The Python module `surfreg`: the libraries' types and entry points —
// Surface (measure/surface.h, io/surface_reader.h), measure() → Measure
// (measure/measures.h), align() → Alignment (registration/align.h) and
// terrain_change() → TerrainChange (terrain/terrain_measure.h), series() →
// Series (registration/series.h), asymmetry() → Asymmetry (faces_module.cc). Options are
// keywords with the names, values and messages of the config keys, from the
// libraries' key tables (measure/measure_keys.h, registration/align_keys.h,
// terrain/terrain_keys.h). The CLI's code is not linked.
#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cmath>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "io/surface_reader.h"
#include "measure/input_error.h"
#include "measure/measure_keys.h"
#include "measure/measures.h"
#include "registration/align.h"
#include "registration/align_keys.h"
#include "registration/series.h"
#include "terrain/series_epochs.h"
#include "terrain/terrain_keys.h"
#include "terrain/terrain_measure.h"
#include "tools/python/python_values.h"

namespace py = pybind11;

namespace surfreg::python {

void BindFaces(py::module_& m);  // tools/python/faces_module.cc

namespace {

std::string Keyword(const py::handle& name) { return "keyword '" + py::str(name).cast<std::string>() + "'"; }

py::array_t<double> Array(const std::vector<double>& values) {
  return py::array_t<double>(static_cast<py::ssize_t>(values.size()), values.data());
}

// The samples in input coordinates (origin + local), (N, 3).
py::array_t<double> Points(const Surface& s) {
  py::array_t<double> out({static_cast<py::ssize_t>(s.size()), py::ssize_t{3}});
  auto p = out.mutable_unchecked<2>();
  for (std::size_t i = 0; i < s.size(); ++i) {
    p(i, 0) = s.origin[0] + s.xy[i].x;
    p(i, 1) = s.origin[1] + s.xy[i].y;
    p(i, 2) = s.origin[2] + s.z[i];
  }
  return out;
}

Surface ReadSurfacePy(const py::object& path, const py::object& classes, const py::object& columns) {
  if (!IsPath(path)) throw InputError("argument path: expected a file path");
  ReadOptions options;
  if (!classes.is_none()) options.classes = classes.cast<std::vector<int>>();
  if (!columns.is_none()) {
    for (const py::handle c : columns) options.columns.push_back(py::str(c).cast<std::string>());
  }
  const std::string text = PathText(path);
  py::gil_scoped_release release;
  return ReadSurface(text, options);
}

MeasureSummary MeasurePy(const py::object& a, const py::object& b, const py::kwargs& kwargs) {
  MeasureOptions options;
  for (const auto& [name, value] : kwargs) {
    SetOption(MeasureOptionKeys(), py::str(name).cast<std::string>(), ValueOf(value, Keyword(name)), &options);
  }
  const Surface sa = SurfaceOf(a, "array A"), sb = SurfaceOf(b, "array B");
  py::gil_scoped_release release;  // the inputs are C++ copies by now
  return Measure(sa, sb, options);
}

AlignResult AlignPy(const py::object& reference, const py::object& moving, const py::object& initial_matrix,
                    const py::kwargs& kwargs) {
  AlignOptions options;
  for (const auto& [name, value] : kwargs) {
    SetAlignOption(py::str(name).cast<std::string>(), ValueOf(value, Keyword(name)), &options);
  }
  if (!initial_matrix.is_none()) {
    const Eigen::Matrix4d m = initial_matrix.cast<Eigen::Matrix4d>();
    if (!IsRigid(m)) {
      throw InputError("keyword 'initial_matrix': not a rigid motion (a rotation and a shift, last row 0 0 0 1)");
    }
    options.initial_reference_from_moving = Rigid3d::FromMatrix(m);
  }
  std::string error;
  if (!options.IsValid(&error)) throw InputError(error);
  const Surface r = SurfaceOf(reference, "array reference"), m = SurfaceOf(moving, "array moving");
  py::gil_scoped_release release;
  return Align(r, m, options);
}

TerrainMeasure TerrainChangePy(const py::object& reference, const py::object& moving, const py::kwargs& kwargs) {
  TerrainRequest request;
  MeasureOptions options;
  options.detect_change = true;
  for (const auto& [name, value] : kwargs) {
    const std::string key = py::str(name).cast<std::string>();
    config_value::Value v = ValueOf(value, Keyword(name));
    if (const TerrainSettingEntry* entry = FindTerrainSetting(key)) {
      v.expected = entry->key.type;
      entry->set(v, &request.terrain);
      if (key == "dod" || key == "dod_sigma" || key == "dod_thresholded") {
        CheckTerrainOutput(key, entry->get(request.terrain), v.where);
      }
      request.origin[key] = v.where;
    } else {
      SetOption(MeasureOptionKeys(), key, std::move(v), &options);
    }
  }
  for (const char* key : {"dod_png", "histogram_png", "change_csv", "known_matrix", "max_memory", "tile_stats",
                          "patch_shifts", "mask_raster"}) {
    if (request.Given(key)) throw InputError(request.Where(key) + ": terrain_change does not take it (align's key)");
  }
  std::optional<Surface> a, b;
  if (IsPath(reference)) request.reference = PathText(reference); else a = SurfaceOf(reference, "array reference");
  if (IsPath(moving)) request.moving = PathText(moving); else b = SurfaceOf(moving, "array moving");
  if (a) request.reference = a->source;
  if (b) request.moving = b->source;
  py::gil_scoped_release release;
  return MeasureTerrain(request, options, "", "mask", a ? &*a : nullptr, b ? &*b : nullptr);
}

SeriesResult SeriesPy(const py::sequence& surfaces, int reference, const py::object& pairs,
                      double min_overlap, const py::kwargs& kwargs) {
  SeriesOptions options;
  options.reference = reference;
  options.min_overlap = min_overlap;
  if (!pairs.is_none()) options.pairs = pairs.cast<std::vector<std::pair<int, int>>>();
  // crs and frame: how files are brought into one metric frame, as the CLI's
  // keys (terrain/series_epochs.h); every other keyword is an align option.
  std::string crs, crs_where = "keyword 'crs'", frame = "auto";
  for (const auto& [name, value] : kwargs) {
    const std::string key = py::str(name).cast<std::string>();
    config_value::Value v = ValueOf(value, Keyword(name));
    if (key == "crs") {
      crs = config_value::Path(v, false);
      crs_where = v.where;
    } else if (key == "frame") {
      TerrainSettings settings;
      const TerrainSettingEntry* entry = FindTerrainSetting("frame");
      v.expected = entry->key.type;
      entry->set(v, &settings);
      frame = settings.frame;
    } else {
      SetAlignOption(key, std::move(v), &options.align);
    }
  }
  std::vector<std::string> paths;
  for (const py::handle item : surfaces) {
    if (IsPath(item)) paths.push_back(PathText(item));
  }
  if (paths.size() == surfaces.size()) {  // files: read as `surfreg series` reads them
    py::gil_scoped_release release;
    ReadOptions read;
    read.threads = options.align.num_threads;
    SeriesEpochs epochs = ReadSeriesEpochs(paths, read, crs, crs_where, frame);
    SeriesResult result = AlignSeries(epochs.surfaces, options);
    result.frame = epochs.frame.Describe();
    return result;
  }
  if (!crs.empty()) throw InputError(crs_where + ": applies when every surface is a file");
  std::vector<Surface> epochs;
  for (std::size_t k = 0; k < surfaces.size(); ++k) {
    epochs.push_back(SurfaceOf(surfaces[k], "epoch " + std::to_string(k)));
  }
  py::gil_scoped_release release;
  SeriesResult result = AlignSeries(epochs, options);
  result.frame = GeoFrame().Describe();
  return result;
}

py::dict Stddev(const std::array<double, 6>& values) {
  py::dict out;
  for (int k = 0; k < 6; ++k) out[kParameterNames[k]] = values[k];
  return out;
}

void BindResults(py::module_& m) {
  py::class_<MeasureSummary>(m, "Measure", "B measured against A (measure/measures.h); lengths in data units")
      .def_readonly("rho_d", &MeasureSummary::rho_d, "the volume between the surfaces over the overlap")
      .def_readonly("rho_d_axial", &MeasureSummary::rho_d_axial, "mean |dz| at the nodes in the overlap")
      .def_readonly("rho_s", &MeasureSummary::rho_s, "1 / rho_d (1 when rho_d = 0)")
      .def_readonly("overlap_area", &MeasureSummary::overlap_area)
      .def_readonly("weight_integral", &MeasureSummary::weight_integral)
      .def_readonly("mean_abs_dz", &MeasureSummary::mean_abs_dz)
      .def_readonly("signed_volume", &MeasureSummary::signed_volume)
      .def_readonly("volume_above", &MeasureSummary::volume_above, "B above A (fill)")
      .def_readonly("volume_below", &MeasureSummary::volume_below, "B below A (cut)")
      .def_readonly("level_of_detection", &MeasureSummary::level_of_detection)
      .def_readonly("fill_detected", &MeasureSummary::fill_detected)
      .def_readonly("cut_detected", &MeasureSummary::cut_detected)
      .def_readonly("fill_area", &MeasureSummary::fill_area)
      .def_readonly("cut_area", &MeasureSummary::cut_area)
      .def_readonly("domain_area_a", &MeasureSummary::domain_area_a)
      .def_readonly("domain_area_b", &MeasureSummary::domain_area_b)
      .def_readonly("n_points_a", &MeasureSummary::n_points_a)
      .def_readonly("n_points_b", &MeasureSummary::n_points_b)
      .def_readonly("n_overlap_nodes", &MeasureSummary::n_overlap_nodes)
      .def_readonly("n_cells", &MeasureSummary::n_cells)
      .def_property_readonly("volume_mode", [](const MeasureSummary& s) { return VolumeModeName(s.volume_mode); })
      .def_property_readonly("domain", [](const MeasureSummary& s) {
        return s.domain_kind == DomainKind::kData ? "data" : "hull";
      })
      .def("report", &MeasureSummary::BriefReport, py::arg("units") = "units",
           "the measures for people, lengths named `units`")
      .def("__repr__", [](const MeasureSummary& s) {
        return "<surfreg.Measure rho_d=" + py::repr(py::float_(s.rho_d)).cast<std::string>() +
               " rho_d_axial=" + py::repr(py::float_(s.rho_d_axial)).cast<std::string>() + ">";
      });

  py::class_<AlignResult>(m, "Alignment", "moving aligned onto reference (registration/align_result.h)")
      .def_readonly("matrix", &AlignResult::matrix, "4 x 4, moving input coordinates -> reference's")
      .def_readonly("rotation_vector", &AlignResult::rotation_vector, "radians")
      .def_readonly("euler_deg", &AlignResult::euler_deg, "rx, ry, rz: R = Rz Ry Rx")
      .def_readonly("translation", &AlignResult::translation, "the shift of the moving centroid")
      .def_readonly("centre", &AlignResult::centre, "the moving centroid, input coordinates")
      .def_property_readonly("stddev", [](const AlignResult& r) { return Stddev(r.stddev); },
                             "standard deviations: rx, ry, rz (radians), tx, ty, tz")
      .def_readonly("covariance", &AlignResult::covariance, "6 x 6, rx ry rz tx ty tz")
      .def_readonly("condition_number", &AlignResult::condition_number)
      .def_readonly("before", &AlignResult::before, "Measure at the initial motion")
      .def_readonly("after", &AlignResult::after, "Measure at the final motion")
      .def_readonly("overlap_fraction_before", &AlignResult::overlap_fraction_before)
      .def_readonly("overlap_fraction_after", &AlignResult::overlap_fraction_after)
      .def_readonly("iterations", &AlignResult::iterations)
      .def_property_readonly("verdict", [](const AlignResult& r) { return VerdictName(r.verdict); })
      .def_readonly("verdict_reason", &AlignResult::verdict_reason)
      .def_readonly("solve_cost", &AlignResult::solve_cost, "the cost solved: volume or axial")
      .def_readonly("wide_search_ran", &AlignResult::wide_search_ran)
      .def_readonly("stddev_source", &AlignResult::stddev_source)
      .def_readonly("seconds", &AlignResult::seconds)
      .def("report", [](const AlignResult& r) { return r.FullReport(); }, "the summary `surfreg align` prints")
      .def("__repr__", [](const AlignResult& r) {
        return std::string("<surfreg.Alignment ") + VerdictName(r.verdict) + ">";
      });

  py::class_<SeriesEpoch>(m, "SeriesEpoch", "one epoch of a series (registration/series.h)")
      .def_readonly("matrix", &SeriesEpoch::matrix,
                    "4 x 4, the epoch's input coordinates -> the reference epoch's")
      .def_readonly("centre", &SeriesEpoch::centre, "the epoch's centroid: the motion's centre")
      .def_readonly("euler_deg", &SeriesEpoch::euler_deg, "rx, ry, rz: R = Rz Ry Rx")
      .def_readonly("translation", &SeriesEpoch::translation, "the shift of the centroid")
      .def_property_readonly(
          "stddev", [](const SeriesEpoch& e) { return Stddev(e.stddev); },
          "the joint standard deviations: rx, ry, rz (radians), tx, ty, tz")
      .def_readonly("covariance", &SeriesEpoch::covariance,
                    "6 x 6, the epoch's block of the joint covariance")
      .def_property_readonly("verdict", [](const SeriesEpoch& e) { return VerdictName(e.verdict); })
      .def_readonly("verdict_reason", &SeriesEpoch::verdict_reason)
      .def_readonly("pairs", &SeriesEpoch::pairs, "the pairs used at this epoch");

  py::class_<SeriesPair>(m, "SeriesPair", "one pair of the series' overlap graph")
      .def_readonly("reference", &SeriesPair::reference)
      .def_readonly("moving", &SeriesPair::moving)
      .def_readonly("overlap", &SeriesPair::overlap,
                    "the footprints' shared share of the smaller one")
      .def_readonly("pairwise", &SeriesPair::pairwise, "the pair's own Alignment")
      .def_readonly("used", &SeriesPair::used)
      .def_readonly("reason", &SeriesPair::reason)
      .def_readonly("before", &SeriesPair::before, "Measure at the input coordinates")
      .def_readonly("after", &SeriesPair::after, "Measure at the joint motion")
      .def_readonly("misclosure_deg", &SeriesPair::misclosure_deg)
      .def_readonly("misclosure_shift", &SeriesPair::misclosure_shift)
      .def_readonly("misclosure_chi2", &SeriesPair::misclosure_chi2);

  py::class_<SeriesResult>(m, "Series", "a series aligned jointly (registration/series.h)")
      .def_readonly("epochs", &SeriesResult::epochs)
      .def_readonly("pairs", &SeriesResult::pairs)
      .def_readonly("reference", &SeriesResult::reference)
      .def_readonly("iterations", &SeriesResult::iterations)
      .def_readonly("termination", &SeriesResult::termination)
      .def_readonly("seconds", &SeriesResult::seconds)
      .def_readonly("pairwise_seconds", &SeriesResult::pairwise_seconds)
      .def_readonly("frame", &SeriesResult::frame,
                    "the coordinates the matrices map: UTM or ENU for lon/lat files; '' as given")
      .def("__repr__", [](const SeriesResult& r) {
        return "<surfreg.Series " + std::to_string(r.epochs.size()) + " epochs, " +
               std::to_string(r.pairs.size()) + " pairs>";
      });

  py::class_<DzStatistics>(m, "DzStatistics", "dz = B - A at A's nodes in the overlap")
      .def_readonly("count", &DzStatistics::count)
      .def_readonly("mean", &DzStatistics::mean)
      .def_readonly("median", &DzStatistics::median)
      .def_readonly("nmad", &DzStatistics::nmad)
      .def_readonly("stddev", &DzStatistics::stddev)
      .def_readonly("rmse", &DzStatistics::rmse)
      .def_readonly("le90", &DzStatistics::le90)
      .def_readonly("min", &DzStatistics::min)
      .def_readonly("max", &DzStatistics::max);

  py::class_<TerrainMeasure>(m, "TerrainChange", "two surveys differenced as they lie (terrain/terrain_measure.h)")
      .def_readonly("measure", &TerrainMeasure::summary, "B against A in the common frame")
      .def_readonly("dz", &TerrainMeasure::dz)
      .def_property_readonly("dz_a", [](const TerrainMeasure& t) { return Array(t.summary.dz_a); },
                             "dz at each sample of A, input order (NaN outside the overlap)")
      .def_property_readonly("fill", [](const TerrainMeasure& t) { return t.summary.fill_detected; })
      .def_property_readonly("cut", [](const TerrainMeasure& t) { return t.summary.cut_detected; })
      .def_property_readonly("net", [](const TerrainMeasure& t) {
        return t.summary.fill_detected - t.summary.cut_detected;
      })
      .def_property_readonly("net_sigma_independent", [](const TerrainMeasure& t) {
        return t.uncertainty.active ? t.uncertainty.budget.net_sigma_independent : std::nan("");
      }, "the net change's sigma, cells independent (NaN without sigma_reference / sigma_moving)")
      .def_property_readonly("net_sigma_correlated", [](const TerrainMeasure& t) {
        return t.uncertainty.active ? t.uncertainty.budget.net_sigma_correlated : std::nan("");
      }, "the net change's sigma, errors fully correlated")
      .def_property_readonly("net_sigma_spatial", [](const TerrainMeasure& t) {
        return t.uncertainty.spatial ? t.uncertainty.net_sigma_spatial : std::nan("");
      }, "the net change's sigma with the DoD's spatially correlated errors (error_model='variogram'; else NaN)")
      .def_property_readonly("fill_sigma_spatial", [](const TerrainMeasure& t) {
        return t.uncertainty.spatial ? t.uncertainty.fill_sigma_spatial : std::nan("");
      })
      .def_property_readonly("cut_sigma_spatial", [](const TerrainMeasure& t) {
        return t.uncertainty.spatial ? t.uncertainty.cut_sigma_spatial : std::nan("");
      })
      .def_property_readonly("variogram", [](const TerrainMeasure& t) {
        py::dict d;
        if (!t.uncertainty.spatial) return d;
        const Variogram& v = t.uncertainty.model.variogram;
        d["nugget"] = v.nugget;
        d["sills"] = py::make_tuple(v.sill[0], v.sill[1]);
        d["ranges"] = py::make_tuple(v.range[0], v.range[1]);
        d["stable_cells"] = t.uncertainty.model.stable_cells;
        return d;
      }, "the fitted variogram of dz / sigma on stable terrain (error_model='variogram'; else empty)")
      .def_property_readonly("frame", [](const TerrainMeasure& t) { return t.frame.Describe(); })
      .def_readonly("b_reprojected_from", &TerrainMeasure::b_reprojected_from)
      .def_readonly("metric", &TerrainMeasure::metric, "lengths in metres")
      .def("report", [](const TerrainMeasure& t) { return t.summary.BriefReport(t.metric ? "m" : "units"); },
           "the measures for people, in metres in a metric frame");
}

}  // namespace
}  // namespace surfreg::python

PYBIND11_MODULE(surfreg, m) {
  using namespace surfreg;
  using namespace surfreg::python;
  m.doc() = "surfreg: the volume between two height-field surfaces, their rigid alignment, and terrain change";
  m.attr("__version__") = SURFREG_VERSION;
  // Bad input: a ValueError (this subclass) with the library's one-line message.
  py::register_exception<InputError>(m, "InputError", PyExc_ValueError);

  py::class_<Surface>(m, "Surface", "a height field z = f(x, y) sampled at points (measure/surface.h)")
      .def(py::init([](const py::object& points, const std::string& name) { return SurfaceFromArray(points, name); }),
           py::arg("points"), py::arg("name") = "array",
           "from an (N, 3) or (N, 4) array of x, y, z[, weight]")
      .def_property_readonly("points", &Points, "(N, 3) x, y, z in input coordinates")
      .def_property_readonly("weights", [](const Surface& s) -> py::object {
        if (s.weight.empty()) return py::none();
        return Array(s.weight);
      })
      .def_readonly("name", &Surface::source)
      .def_property_readonly("is_raster", &Surface::raster_grid)
      .def("__len__", &Surface::size)
      .def("__repr__", [](const Surface& s) {
        return "<surfreg.Surface '" + s.source + "' " + std::to_string(s.size()) + " points>";
      });
  BindResults(m);
  BindFaces(m);

  m.def("read_surface", &ReadSurfacePy, py::arg("path"), py::arg("classes") = py::none(),
        py::arg("columns") = py::none(),
        "read_surface(path, classes=None, columns=None) -> Surface\n\n"
        "A surface file (.xyz .txt .csv .ply .off .obj .las, or a GDAL raster); classes: LAS\n"
        "classifications kept; columns: a text cloud's x, y, z[, weight] columns.");
  m.def("measure", &MeasurePy, py::arg("a"), py::arg("b"),
        "measure(a, b, **options) -> Measure\n\n"
        "B against A. A surface is a Surface, a file path or an (N, 3) / (N, 4) array.\n"
        "Options: volume, weights, lod, min_overlap_fraction, domain, domain_max_edge_spacings,\n"
        "domain_min_thinness (docs/measure.md).");
  m.def("align", &AlignPy, py::arg("reference"), py::arg("moving"), py::arg("initial_matrix") = py::none(),
        "align(reference, moving, initial_matrix=None, **options) -> Alignment\n\n"
        "The rigid motion of moving onto reference (matrix: moving -> reference, input\n"
        "coordinates), the measures before and after, sigma and the verdict. initial_matrix:\n"
        "a 4 x 4 start. Options: align's option keys (cost, free, levels, max_iterations,\n"
        "stable, ...; docs/align.md).");
  m.def("series", &SeriesPy, py::arg("surfaces"), py::arg("reference") = 0,
        py::arg("pairs") = py::none(), py::arg("min_overlap") = 0.3,
        "series(surfaces, reference=0, pairs=None, min_overlap=0.3, **options) -> Series\n\n"
        "A series of surveys aligned jointly: one motion per epoch into the reference epoch's\n"
        "frame, over every pair that overlaps by min_overlap (or the (i, j) pairs given).\n"
        "Surfaces: Surface objects, file paths or (N, 3) arrays. Files in lon/lat are solved\n"
        "in metres (frame= auto, utm or enu; crs= for files that do not carry one). Options:\n"
        "align's option keys, applied to each pair (docs/series.md).");
  m.def("terrain_change", &TerrainChangePy, py::arg("reference"), py::arg("moving"),
        "terrain_change(reference, moving, **keys) -> TerrainChange\n\n"
        "Two DEMs or clouds (files or arrays) in one metric frame, differenced as they lie:\n"
        "dz statistics at the reference's nodes, cut and fill beyond lod, the change budget\n"
        "with sigma_reference / sigma_moving, the DoD GeoTIFF with dod=. Keys: the terrain\n"
        "keys (reference_crs, moving_crs, frame, band, window, lod, sigma_*, lod_confidence,\n"
        "dod, dod_sigma, dod_thresholded, error_model; docs/terrain.md) and measure()'s options.");
}
