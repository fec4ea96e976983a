// surfreg normalize MESH [--orientation=auto|as_is|RX,RY,RZ] [--depth_limit=D]
// [--output=FACE.xyz|.ply] [--json]: a face mesh or cloud in the standard
// face frame (faces/face_frame.h); writes its visible height field and
// reports the transform.
#include <gflags/gflags.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "faces/face_frame.h"
#include "measure/input_error.h"
#include "io/atomic_file.h"
#include "tools/commands.h"
#include "tools/face_orientation.h"
#include "io/mesh_reader.h"
#include "io/surface_writer.h"
#include "tools/json_writer.h"
#include "tools/key_flags.h"

// Shared with the other face commands (asymmetry, jaw): DECLARE them there.
DEFINE_string(orientation, "auto",
              "normalize, asymmetry: auto (principal axes + nose heuristics), as_is (already in "
              "the face frame) or RX,RY,RZ (rotation vector, degrees, input -> frame)");
DEFINE_double(depth_limit, 0.0,
              "normalize, asymmetry: keep points at most this far behind the nose tip (data "
              "units; 0 = all visible points)");

namespace surfreg {
namespace {

std::string Number(double value) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.10g", value + 0.0);
  return text;
}

std::vector<std::string> Numbers(const double* values, int n) {
  std::vector<std::string> out;
  for (int i = 0; i < n; ++i) out.push_back(JsonNumber(values[i]));
  return out;
}

// The rotation as a rotation vector (axis × angle) in degrees.
std::array<double, 3> RotationVectorDeg(const FaceFrame& frame) {
  Eigen::Matrix3d r;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) r(i, j) = frame.rotation[3 * i + j];
  }
  const Eigen::AngleAxisd angle_axis(r);
  const Eigen::Vector3d v = angle_axis.axis() * angle_axis.angle() * (45.0 / std::atan(1.0));
  return {v.x(), v.y(), v.z()};
}

// The input vertex that became the nose tip (the first kept point at z = 0).
std::array<double, 3> NoseTipInput(const Mesh& mesh, const FaceFrame& frame) {
  std::size_t i = 0;
  while (i + 1 < frame.points.size() && frame.points[i][2] != 0.0) ++i;
  return mesh.vertices[frame.input_index[i]];
}

void PrintText(const std::string& file, const Mesh& mesh, const FaceFrameOptions& options,
               const FaceFrame& frame) {
  const std::array<double, 3> rv = RotationVectorDeg(frame);
  std::printf("mesh:         %s  (%zu vertices, %zu triangles)\n", file.c_str(),
              mesh.vertices.size(), mesh.triangles.size());
  std::printf("orientation:  %s\n", FaceOrientationToString(options).c_str());
  std::printf("kept:         %zu points  (%lld hidden, %lld beyond depth_limit %s)\n",
              frame.points.size(), static_cast<long long>(frame.hidden),
              static_cast<long long>(frame.beyond_depth), Number(options.depth_limit).c_str());
  for (int i = 0; i < 3; ++i) {
    std::printf("%s [% .9f % .9f % .9f]\n", i == 0 ? "rotation:    " : "             ",
                frame.rotation[3 * i], frame.rotation[3 * i + 1], frame.rotation[3 * i + 2]);
  }
  std::printf("rotation vector: (%s, %s, %s) deg  (%s deg about its axis)\n", Number(rv[0]).c_str(),
              Number(rv[1]).c_str(), Number(rv[2]).c_str(),
              Number(std::sqrt(rv[0] * rv[0] + rv[1] * rv[1] + rv[2] * rv[2])).c_str());
  std::printf("translation:  (%s, %s, %s)  (frame = rotation * input + translation)\n",
              Number(frame.translation[0]).c_str(), Number(frame.translation[1]).c_str(),
              Number(frame.translation[2]).c_str());
  const std::array<double, 3> tip = NoseTipInput(mesh, frame);
  std::printf("nose tip:     (%s, %s, 0) in the frame; (%s, %s, %s) in the input\n",
              Number(frame.nose_tip[0]).c_str(), Number(frame.nose_tip[1]).c_str(),
              Number(tip[0]).c_str(), Number(tip[1]).c_str(), Number(tip[2]).c_str());
  if (!KeyFlag("output").empty()) std::printf("written:      %s\n", KeyFlag("output").c_str());
}

void PrintJson(const std::string& file, const Mesh& mesh, const FaceFrameOptions& options,
               const FaceFrame& frame) {
  const std::array<double, 3> rv = RotationVectorDeg(frame);
  JsonObject json;
  json.String("mesh", file)
      .Int("vertices", static_cast<int64_t>(mesh.vertices.size()))
      .Int("triangles", static_cast<int64_t>(mesh.triangles.size()))
      .String("orientation", FaceOrientationToString(options))
      .Number("depth_limit", options.depth_limit)
      .Int("kept", static_cast<int64_t>(frame.points.size()))
      .Int("hidden", frame.hidden)
      .Int("beyond_depth", frame.beyond_depth)
      .Raw("rotation", JsonArray(Numbers(frame.rotation.data(), 9)))
      .Raw("rotation_vector_deg", JsonArray(Numbers(rv.data(), 3)))
      .Raw("translation", JsonArray(Numbers(frame.translation.data(), 3)))
      .Raw("nose_tip", JsonArray(Numbers(frame.nose_tip.data(), 3)))
      .Raw("nose_tip_input", JsonArray(Numbers(NoseTipInput(mesh, frame).data(), 3)));
  if (!KeyFlag("output").empty()) json.String("output", KeyFlag("output"));
  std::printf("%s\n", json.str().c_str());
}

}  // namespace

int RunNormalize(const std::vector<std::string>& args) {
  if (args.empty()) throw UsageError("normalize: missing MESH");
  if (args.size() > 1) throw UsageError("normalize: too many arguments");
  // Flags and the output path first: a mistake is reported before any work.
  FaceFrameOptions options;
  FaceOrientationFromString(FLAGS_orientation, "flag '--orientation'", &options);
  if (!(FLAGS_depth_limit >= 0.0) || !std::isfinite(FLAGS_depth_limit)) {
    throw InputError("flag '--depth_limit': expected a number >= 0, got " +
                     Number(FLAGS_depth_limit));
  }
  options.depth_limit = FLAGS_depth_limit;
  if (!KeyFlag("output").empty()) {
    if (!IsWritableSurfacePath(KeyFlag("output"))) {
      throw InputError("flag '--output': " + KeyFlag("output") +
                       ": unknown output format (expected .xyz, .txt, .ply or .las)");
    }
    CheckOutputPath(KeyFlag("output"), "flag '--output'");
  }
  const Mesh mesh = ReadMesh(args[0]);
  const FaceFrame frame = NormalizeFace(mesh, options);
  if (!KeyFlag("output").empty()) {
    std::string rotation;
    for (int k = 0; k < 9; ++k) rotation += (k ? " " : "") + JsonNumber(frame.rotation[k]);
    const std::vector<std::string> comments = {
        "face frame of " + args[0] + " (surfreg normalize, orientation " +
            FaceOrientationToString(options) + ", depth_limit " + Number(options.depth_limit) + ")",
        "frame = rotation * input + translation; rotation (row-major): " + rotation,
        "translation: " + JsonNumber(frame.translation[0]) + " " +
            JsonNumber(frame.translation[1]) + " " + JsonNumber(frame.translation[2]),
    };
    WriteSurface(KeyFlag("output"), FaceSurface(frame, args[0]), "flag '--output'", comments);
  }
  if (FLAGS_json) {
    PrintJson(args[0], mesh, options, frame);
  } else {
    PrintText(args[0], mesh, options, frame);
  }
  return 0;
}

}  // namespace surfreg
