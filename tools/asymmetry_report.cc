#include "tools/asymmetry_report.h"

#include <cctype>
#include <cmath>
#include <cstdio>
#include <string>

#include "io/atomic_file.h"
#include "io/polygon_reader.h"
#include "measure/input_error.h"
#include "tools/face_orientation.h"

namespace surfreg {
namespace {

std::string Format(const char* format, double value) {
  char text[64];
  std::snprintf(text, sizeof(text), format, value + 0.0);
  return text;
}

std::string Triple(const std::array<double, 3>& v) {
  return JsonArray({JsonNumber(v[0]), JsonNumber(v[1]), JsonNumber(v[2])});
}

JsonObject EstimateJson(const SymmetryEstimate& e) {
  JsonObject plane;
  plane.Raw("normal", Triple(e.plane.normal)).Number("offset", e.plane.offset);
  const MeasureSummary& m = e.measure;
  JsonObject json;
  json.Number("rho_d", m.rho_d)
      .Number("mean_abs_dz", m.mean_abs_dz)
      .Number("overlap_area", m.overlap_area)
      .Object("plane", plane)
      .Number("rho_d_per_area", m.overlap_area > 0 ? m.rho_d / m.overlap_area : 0.0)
      .Number("rho_d_axial", m.rho_d_axial)
      .Number("signed_volume", m.signed_volume)
      .Number("volume_above", m.volume_above)
      .Number("volume_below", m.volume_below)
      .Int("n_overlap_nodes", m.n_overlap_nodes);
  return json;
}

JsonObject RegionJson(const RegionIndex& r) {
  JsonObject json;
  json.Number("rms", r.rms)
      .Number("rms_sigma", r.rms_sigma)
      .Number("mean_abs", r.mean_abs)
      .Number("mean_abs_sigma", r.mean_abs_sigma)
      .Number("mean", r.mean)
      .Number("mean_sigma", r.mean_sigma)
      .Number("volume", r.volume)
      .Number("volume_sigma", r.volume_sigma)
      .Number("max_abs", r.max_abs)
      .Number("area", r.area)
      .Int("nodes", r.nodes);
  return json;
}

}  // namespace

bool EndsWithLower(const std::string& path, const char* tail) {
  const std::string t(tail);
  if (path.size() < t.size()) return false;
  for (std::size_t k = 0; k < t.size(); ++k) {
    if (std::tolower(static_cast<unsigned char>(path[path.size() - t.size() + k])) != t[k])
      return false;
  }
  return true;
}

std::vector<FaceRegion> ReadFaceRegions(const std::string& spec, const std::string& where) {
  std::vector<FaceRegion> regions;
  std::size_t start = 0;
  while (start <= spec.size()) {
    std::size_t end = spec.find(',', start);
    if (end == std::string::npos) end = spec.size();
    const std::string item = spec.substr(start, end - start);
    start = end + 1;
    const std::size_t colon = item.find(':');
    if (colon == std::string::npos || colon == 0 || colon + 1 == item.size()) {
      throw InputError(where + ": expected NAME:FILE[,NAME:FILE...], got '" + item + "'");
    }
    regions.push_back({item.substr(0, colon), ReadPolygon(item.substr(colon + 1))});
  }
  return regions;
}

JsonObject FaceAsymmetryJson(const FaceAsymmetry& a, const std::string& map_path) {
  const SymmetryResult& r = a.symmetry;
  const AsymmetryIndices& x = a.indices;
  JsonObject regions;
  regions.Object(x.whole.name, RegionJson(x.whole));
  for (const RegionIndex& region : x.regions) regions.Object(region.name, RegionJson(region));
  JsonObject plane_sigma;
  plane_sigma.Number("tilt_y_deg", x.plane_sigma[0])
      .Number("tilt_z_deg", x.plane_sigma[1])
      .Number("offset", x.plane_sigma[2]);
  JsonObject json;
  json.String("face", a.file)
      .String("orientation", FaceOrientationToString(a.frame_options))
      .Number("depth_limit", a.frame_options.depth_limit)
      .Int("points", static_cast<int64_t>(a.face.size()))
      .Object("initial", EstimateJson(r.initial))
      .Object("refined", EstimateJson(r.refined))
      .Raw("improved", r.improved ? "true" : "false")
      .String("note", r.note)
      .Number("angle_deg", r.angle_deg)
      .Object("plane_sigma", plane_sigma)
      .Number("noise_sigma", x.noise_sigma)
      .Raw("thirds_y", JsonNumbers({x.thirds_y.begin(), x.thirds_y.end()}))
      .Object("regions", regions);
  if (!a.z_scores.empty()) {
    JsonObject z;
    for (const ZScore& s : a.z_scores) z.Number(s.name, s.z);
    json.Object("z_scores", z);
  }
  json.Int("iterations", r.iterations)
      .String("termination", r.termination)
      .Fixed("seconds_refine", r.seconds_refine, 4)
      .Fixed("seconds", r.seconds, 4);
  if (!map_path.empty()) json.String("map", map_path);
  return json;
}

std::string RegionTable(const FaceAsymmetry& a, const std::string& units) {
  const bool z = !a.z_scores.empty();
  const auto z_of = [&](const std::string& name) -> std::string {
    for (const ZScore& s : a.z_scores) {
      if (s.name == name) return Format("%+.2f", s.z);
    }
    return "-";
  };
  char line[512];
  std::snprintf(line, sizeof(line), "  %-14s %-22s %-22s %10s %10s %10s%s\n", "region",
                ("rms (" + units + ")").c_str(), ("mean |d| (" + units + ")").c_str(), "mean d",
                "max |d|", "area", z ? "   z(rms)" : "");
  std::string text = line;
  const auto row = [&](const RegionIndex& r) {
    std::snprintf(line, sizeof(line), "  %-14s %-22s %-22s %10.4g %10.4g %10.4g%s\n",
                  r.name.c_str(),
                  (Format("%.4g", r.rms) + " ± " + Format("%.2g", r.rms_sigma)).c_str(),
                  (Format("%.4g", r.mean_abs) + " ± " + Format("%.2g", r.mean_abs_sigma)).c_str(),
                  r.mean, r.max_abs, r.area, z ? ("   " + z_of(r.name + "_rms")).c_str() : "");
    text += line;
  };
  row(a.indices.whole);
  for (const RegionIndex& r : a.indices.regions) row(r);
  return text;
}

void PrintFaceAsymmetry(const FaceAsymmetry& a, const std::string& units) {
  const SymmetryResult& r = a.symmetry;
  std::printf("face:  %s  (%zu points in the face frame, orientation %s)\n", a.file.c_str(),
              a.face.size(), FaceOrientationToString(a.frame_options).c_str());
  const auto plane = [](const SymmetryPlane& p) {
    return "(" + Format("%.6f", p.normal[0]) + ", " + Format("%.6f", p.normal[1]) + ", " +
           Format("%.6f", p.normal[2]) + "), offset " + Format("%.6g", p.offset);
  };
  std::printf("plane: x = 0 -> %s; %.4f deg apart (sigma %.2g, %.2g deg, offset %.2g %s)\n",
              plane(r.refined.plane).c_str(), r.angle_deg, a.indices.plane_sigma[0],
              a.indices.plane_sigma[1], a.indices.plane_sigma[2], units.c_str());
  std::printf("rho_d %.6g -> %.6g %s^3; mean |dz| %.6g -> %.6g %s; overlap %.6g %s^2\n",
              r.initial.measure.rho_d, r.refined.measure.rho_d, units.c_str(),
              r.initial.measure.mean_abs_dz, r.refined.measure.mean_abs_dz, units.c_str(),
              r.refined.measure.overlap_area, units.c_str());
  std::printf(
      "d = face - mirror about the refined plane (> 0: this side stands out); noise %.3g %s; "
      "thirds "
      "at y = %.4g, %.4g, %.4g, %.4g\n",
      a.indices.noise_sigma, units.c_str(), a.indices.thirds_y[0], a.indices.thirds_y[1],
      a.indices.thirds_y[2], a.indices.thirds_y[3]);
  std::printf("%s", RegionTable(a, units).c_str());
  std::printf("refinement: %d iterations, %.3f s (%s); total %.3f s\n", r.iterations,
              r.seconds_refine, r.termination.c_str(), r.seconds);
  if (!r.note.empty()) std::printf("note: %s\n", r.note.c_str());
}

void WritePointDifferences(const FaceAsymmetry& a, const std::string& path,
                           const std::string& where) {
  const bool ply = EndsWithLower(path, ".ply");
  const std::vector<double>& d = a.indices.node_difference;
  std::string out;
  out.reserve(d.size() * 64);
  if (ply) {
    out =
        "ply\nformat ascii 1.0\ncomment surfreg asymmetry: difference = face - mirror (NaN outside "
        "the "
        "overlap)\nelement vertex " +
        std::to_string(d.size()) +
        "\nproperty double x\nproperty double y\nproperty double z\nproperty double "
        "difference\nend_header\n";
  } else {
    out = "x,y,z,difference,input_index\n";
  }
  char line[160];
  for (std::size_t i = 0; i < d.size(); ++i) {
    const auto& p = a.frame.points[i];
    if (ply) {
      std::snprintf(line, sizeof(line), "%.10g %.10g %.10g %.9g\n", p[0], p[1], p[2], d[i]);
    } else {
      std::snprintf(line, sizeof(line), "%.10g,%.10g,%.10g,%.9g,%d\n", p[0], p[1], p[2], d[i],
                    a.frame.input_index.empty() ? static_cast<int>(i) : a.frame.input_index[i]);
    }
    out += line;
  }
  WriteFileAtomically(path, out, where);
}

}  // namespace surfreg
