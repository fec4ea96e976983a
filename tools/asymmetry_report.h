#pragma once
// What `surfreg asymmetry` prints and writes for one face (tools/run_asymmetry.cc
// parses the flags and picks the mode): the JSON object, the text summary,
// the per-point file, and the regions read from polygon files.
#include <string>
#include <vector>

#include "faces/asymmetry_cohort.h"
#include "faces/asymmetry_index.h"
#include "faces/face_frame.h"
#include "faces/symmetry.h"
#include "measure/surface.h"
#include "tools/json_writer.h"

namespace surfreg {

// One face's results.
struct FaceAsymmetry {
  std::string file;
  FaceFrameOptions frame_options;
  FaceFrame frame;  // the face in the standard frame (points, input_index)
  Surface face;
  SymmetryResult symmetry;
  AsymmetryIndices indices;      // about the refined plane
  std::vector<ZScore> z_scores;  // against --norms, if given
};

// Whether `path` ends with `tail` (lower case), ignoring the path's case.
bool EndsWithLower(const std::string& path, const char* tail);

// "NAME:FILE[,NAME:FILE...]" (the --regions flag) read into regions; throws
// InputError naming the flag, or the polygon file and line.
std::vector<FaceRegion> ReadFaceRegions(const std::string& spec, const std::string& where);

JsonObject FaceAsymmetryJson(const FaceAsymmetry& a, const std::string& map_path);
void PrintFaceAsymmetry(const FaceAsymmetry& a, const std::string& units);

// The difference at every kept point: CSV "x,y,z,difference,input_index" or
// ASCII PLY (x y z difference, float), by the path's extension; face-frame
// coordinates; NaN outside the overlap. Written atomically.
void WritePointDifferences(const FaceAsymmetry& a, const std::string& path,
                           const std::string& where);

// The regions' indices as text rows (name, rms ± σ, mean |d| ± σ, mean, max, area, z).
std::string RegionTable(const FaceAsymmetry& a, const std::string& units);

}  // namespace surfreg
