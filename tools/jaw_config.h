#pragma once
// The settings of `surfreg jaw` (docs/faces.md): one table of keys, read from
// a YAML mapping and from --KEY=VALUE flags of the same names, with the
// precedence JawOptions' defaults < the config file < flags. Relative paths
// are used as given (relative to the current directory), as for `align`.
//
// Keys (defaults in brackets; docs/faces.md, jaw):
//   frames            a folder (its surface files sorted by name: .xyz .txt
//                     .csv .ply .off .obj) or a list of files   [required]
//   reference         index of the reference frame (0-based) or one of the
//                     frame files                                [0]
//   orientation       as_is (frames used as given) | auto (principal axes
//                     and nose heuristics) | [rx, ry, rz] degrees: the face
//                     frame computed ONCE on the reference (NormalizeFace)
//                     and applied to every frame                 [as_is]
//   boundary_y        y level: y ≥ level is upper, below lower   [none]
//   boundary_polygon  polygon file (x y per line): inside = lower [none]
//   boundary_margin   points this close to the boundary are dropped [0]
//   path_point        [x, y, z]: the point whose path is reported, in the
//                     reference frame (data units)  [the lowest lower-part point]
//   cost              axial | volume (axial, then volume_iterations of ρd) [axial]
//   trim_fraction, max_iterations, step_tolerance, volume_iterations,
//   normal_distance, predict, max_fold_fraction, threads, min_part_points:
//                     JawOptions' fields of the same names (faces/jaw.h)
//   output_csv        per-frame CSV (frame,rx_deg,...,tz, then details) [none]
//   output_json       per-frame 4×4 matrices and details        [none]
//   plot              PNG of the six motion parameters over the frames [none]
//   path_plot         PNG of the path point's displacement, sagittal and frontal [none]
//   progress          one line per frame on stderr               [true]
// At most one of boundary_y and boundary_polygon; neither: the level is found
// from the sequence (JawOptions::find_boundary, faces/jaw_split.h).
//
// Errors: InputError with one line naming where ("jaw.yaml:3: key 'cost'",
// "flag '--cost'") and what; unknown keys get a "did you mean".
#include <array>
#include <map>
#include <string>
#include <vector>

#include "faces/face_frame.h"
#include "faces/jaw.h"
#include "measure/option_keys.h"

namespace surfreg {

struct JawConfig {
  // As given: a folder (one item) or files; FinishJawConfig fills frame_files.
  std::vector<std::string> frames;
  std::vector<std::string> frame_files;  // the frames in order
  std::string reference = "0";           // index or file, as given
  int reference_index = 0;               // resolved by FinishJawConfig
  FaceFrameOptions orientation = AsIsOrientation();
  bool has_boundary_y = false;
  std::string boundary_polygon;  // file; "" = none
  JawOptions options;            // boundary (polygon read by FinishJawConfig) and solver settings
  std::string output_csv, output_json, plot, path_plot;
  bool progress = true;
  std::string config_file;
  // Where each key was last set ("jaw.yaml:3: key 'cost'", "flag '--cost'").
  std::map<std::string, std::string> origin;

  std::string Where(const std::string& key) const;  // origin[key] or "key 'KEY'"
  static FaceFrameOptions AsIsOrientation();
};

using JawConfigKey = ConfigKey;

// Every key, in the order of the documentation above.
const std::vector<JawConfigKey>& JawConfigKeys();

// The value of `key` as YAML text ("axial", "[0, 0, 0]"); "" for a file key
// naming no file. Throws InputError for an unknown key.
std::string JawConfigValue(const JawConfig& config, const std::string& key);

// Applies the YAML mapping `yaml_text` (`file` names it in messages).
void ApplyJawYaml(const std::string& yaml_text, const std::string& file, JawConfig* config);
// Reads the file at `path` (errors name "flag '--config'") and applies it.
void ApplyJawConfigFile(const std::string& path, JawConfig* config);
// A flag --KEY=VALUE (booleans "true"/"false"; lists "a,b" or "[a, b]").
void ApplyJawFlag(const std::string& key, const std::string& value, JawConfig* config);

// Once every setting is applied: lists the frames (a missing file, a folder
// without surface files, or fewer than 2 frames are errors naming 'frames'),
// resolves the reference, reads the boundary polygon, checks that at most
// one boundary is given (none: find_boundary), the outputs can be written (directories exist,
// plot ends in .png, no output names a frame or another output) and the
// options as a whole (JawOptions::IsValid). Throws InputError naming the key.
void FinishJawConfig(JawConfig* config);

}  // namespace surfreg
