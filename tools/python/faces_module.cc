// The faces part of the Python module (tools/python/surfreg_module.cc):
// asymmetry() → Asymmetry, the face against its mirror image about the
// optimized plane and the indices by region (faces/symmetry.h,
// faces/asymmetry_index.h, faces/asymmetry_cohort.h), as `surfreg
// asymmetry` computes them.
#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "faces/asymmetry_cohort.h"
#include "faces/asymmetry_index.h"
#include "faces/face_frame.h"
#include "faces/symmetry.h"
#include "io/mesh_reader.h"
#include "io/polygon_reader.h"
#include "measure/input_error.h"
#include "tools/python/python_values.h"

namespace py = pybind11;

namespace surfreg::python {
namespace {

struct FaceAsymmetryPy {
  FaceFrame frame;
  SymmetryResult symmetry;
  AsymmetryIndices indices;
  std::vector<ZScore> z_scores;
};

py::dict RegionDict(const RegionIndex& r) {
  py::dict d;
  d["rms"] = r.rms;
  d["rms_sigma"] = r.rms_sigma;
  d["mean_abs"] = r.mean_abs;
  d["mean_abs_sigma"] = r.mean_abs_sigma;
  d["mean"] = r.mean;
  d["mean_sigma"] = r.mean_sigma;
  d["volume"] = r.volume;
  d["volume_sigma"] = r.volume_sigma;
  d["max_abs"] = r.max_abs;
  d["area"] = r.area;
  d["nodes"] = r.nodes;
  return d;
}

py::dict PlaneDict(const SymmetryPlane& p) {
  py::dict d;
  d["normal"] = p.normal;
  d["offset"] = p.offset;
  return d;
}

// A face file (a mesh with triangles is oriented automatically, a cloud is
// taken as already in the face frame, as the CLI does) or an (N, 3) array
// of face-frame points.
Mesh FaceMesh(const py::object& face, FaceFrameOptions* options) {
  if (IsPath(face)) {
    Mesh mesh = ReadMesh(PathText(face));
    if (mesh.triangles.empty()) options->orientation = FaceOrientation::kAsIs;
    return mesh;
  }
  const Surface s = SurfaceOf(face, "array face");
  Mesh mesh;
  mesh.source = s.source;
  for (std::size_t i = 0; i < s.size(); ++i) {
    mesh.vertices.push_back(
        {s.origin[0] + s.xy[i].x, s.origin[1] + s.xy[i].y, s.origin[2] + s.z[i]});
  }
  options->orientation = FaceOrientation::kAsIs;
  return mesh;
}

FaceAsymmetryPy AsymmetryPy(const py::object& face, const py::object& regions,
                            const py::object& norms, double depth_limit) {
  FaceFrameOptions frame_options;
  frame_options.depth_limit = depth_limit;
  AsymmetryIndexOptions index_options;
  if (!regions.is_none()) {
    for (const auto& [name, value] : regions.cast<py::dict>()) {
      const std::string key = py::str(name).cast<std::string>();
      FaceRegion region{key, {}};
      if (IsPath(value)) {
        region.polygon = ReadPolygon(PathText(value));
      } else {
        region.polygon = value.cast<std::vector<std::array<double, 2>>>();
      }
      index_options.regions.push_back(std::move(region));
    }
  }
  AsymmetryNorms table;
  const bool has_norms = !norms.is_none();
  if (has_norms) {
    if (!IsPath(norms))
      throw InputError(
          "keyword 'norms': expected a table file (as surfreg asymmetry --csv writes)");
    const std::string path = PathText(norms);
    std::ifstream in(path, std::ios::binary);
    if (!in) throw InputError("keyword 'norms': cannot read '" + path + "'");
    std::ostringstream text;
    text << in.rdbuf();
    table = ParseAsymmetryNorms(text.str(), path);
  }
  const Mesh mesh = FaceMesh(face, &frame_options);
  py::gil_scoped_release release;
  FaceAsymmetryPy out;
  out.frame = NormalizeFace(mesh, frame_options);
  const Surface surface = FaceSurface(out.frame, mesh.source);
  out.symmetry = EstimateSymmetry(surface);
  out.indices = ComputeAsymmetryIndices(surface, out.symmetry.refined.plane, index_options);
  if (has_norms) out.z_scores = ZScores(table, IndexValues(out.indices));
  return out;
}

}  // namespace

void BindFaces(py::module_& m) {
  py::class_<FaceAsymmetryPy>(
      m, "Asymmetry",
      "a face against its mirror image (faces/symmetry.h, faces/asymmetry_index.h); "
      "d = face - mirror about the refined plane, in the scan's units")
      .def_property_readonly(
          "plane", [](const FaceAsymmetryPy& a) { return PlaneDict(a.symmetry.refined.plane); },
          "the refined symmetry plane: normal (n_x > 0), offset")
      .def_property_readonly(
          "initial", [](const FaceAsymmetryPy& a) { return a.symmetry.initial.measure; },
          "Measure of the face against its mirror about x = 0")
      .def_property_readonly(
          "refined", [](const FaceAsymmetryPy& a) { return a.symmetry.refined.measure; },
          "Measure about the refined plane")
      .def_property_readonly("angle_deg",
                             [](const FaceAsymmetryPy& a) { return a.symmetry.angle_deg; })
      .def_property_readonly("plane_sigma",
                             [](const FaceAsymmetryPy& a) {
                               py::dict d;
                               d["tilt_y_deg"] = a.indices.plane_sigma[0];
                               d["tilt_z_deg"] = a.indices.plane_sigma[1];
                               d["offset"] = a.indices.plane_sigma[2];
                               return d;
                             })
      .def_property_readonly("noise_sigma",
                             [](const FaceAsymmetryPy& a) { return a.indices.noise_sigma; })
      .def_property_readonly(
          "thirds_y", [](const FaceAsymmetryPy& a) { return a.indices.thirds_y; },
          "the thirds' band edges, bottom to top")
      .def_property_readonly(
          "regions",
          [](const FaceAsymmetryPy& a) {
            py::dict d;
            d[py::str(a.indices.whole.name)] = RegionDict(a.indices.whole);
            for (const RegionIndex& r : a.indices.regions) d[py::str(r.name)] = RegionDict(r);
            return d;
          },
          "per region (face, the thirds, left, right, yours): rms, mean_abs, mean, volume, "
          "max_abs, area, nodes and the sigmas")
      .def_property_readonly(
          "z_scores",
          [](const FaceAsymmetryPy& a) {
            py::dict d;
            for (const ZScore& s : a.z_scores) d[py::str(s.name)] = s.z;
            return d;
          },
          "with norms=: each index's z-score against the cohort table")
      .def_property_readonly(
          "points",
          [](const FaceAsymmetryPy& a) {
            py::array_t<double> out(
                {static_cast<py::ssize_t>(a.frame.points.size()), py::ssize_t{3}});
            auto p = out.mutable_unchecked<2>();
            for (std::size_t i = 0; i < a.frame.points.size(); ++i) {
              for (int k = 0; k < 3; ++k) p(i, k) = a.frame.points[i][k];
            }
            return out;
          },
          "(N, 3) the face's points in the face frame")
      .def_property_readonly(
          "difference",
          [](const FaceAsymmetryPy& a) {
            const auto& d = a.indices.node_difference;
            return py::array_t<double>(static_cast<py::ssize_t>(d.size()), d.data());
          },
          "d at each point (NaN outside the overlap)")
      .def("__repr__", [](const FaceAsymmetryPy& a) {
        return "<surfreg.Asymmetry rms=" +
               py::repr(py::float_(a.indices.whole.rms)).cast<std::string>() + ">";
      });
  m.def("asymmetry", &AsymmetryPy, py::arg("face"), py::arg("regions") = py::none(),
        py::arg("norms") = py::none(), py::arg("depth_limit") = 0.0,
        "asymmetry(face, regions=None, norms=None, depth_limit=0) -> Asymmetry\n\n"
        "The face against its mirror image about the optimized symmetry plane, and the\n"
        "indices by region (docs/faces.md). face: a file (a mesh is oriented automatically,\n"
        "a cloud is taken as in the face frame) or an (N, 3) array in the face frame;\n"
        "regions: {name: polygon file or [(x, y), ...]}; norms: a cohort table written by\n"
        "`surfreg asymmetry FOLDER --csv`.");
}

}  // namespace surfreg::python
