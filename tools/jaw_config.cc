#include "tools/jaw_config.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cctype>
#include <filesystem>

#include "measure/input_error.h"
#include "io/plot.h"
#include "io/atomic_file.h"
#include "tools/config_table.h"
#include "tools/config_value.h"
#include "tools/yaml_value.h"
#include "tools/face_orientation.h"
#include "io/mesh_reader.h"
#include "io/polygon_reader.h"

namespace surfreg {
namespace {

using config_value::Value;
namespace cv = config_value;

using Entry = cv::Entry<JawConfig>;

std::string Join(const std::vector<std::string>& items) {
  if (items.size() == 1) return items[0];
  std::string out = "[";
  for (std::size_t i = 0; i < items.size(); ++i) out += (i ? ", " : "") + items[i];
  return out + "]";
}

const cv::Names<JawCost> kCosts = {{"axial", JawCost::kAxial}, {"volume", JawCost::kVolume}};

const config_table::Table<JawConfig>& Table() {
  using C = JawConfig;
  static const config_table::Table<JawConfig> table(std::vector<Entry>{
      {{"frames", "a folder or a list of surface files", "the sequence"},
       [](const Value& v, C* c) {
         c->frames = cv::Items(v);
         if (c->frames.empty() || std::any_of(c->frames.begin(), c->frames.end(),
                                              [](const std::string& s) { return s.empty(); })) {
           cv::Reject(v);
         }
       },
       [](const C& c) { return c.frames.empty() ? std::string() : Join(c.frames); }},
      {{"reference", "a frame index >= 0 or one of the frame files", "the reference frame (jaw closed)"},
       [](const Value& v, C* c) { c->reference = cv::Path(v, true); },
       [](const C& c) { return c.reference; }},
      {{"orientation", "as_is, auto or [rx, ry, rz] in degrees", "face frame of the reference, applied to all"},
       [](const Value& v, C* c) {
         const std::string text = v.kind == Value::kList ? "[" + Join(cv::Items(v)) + "]" : cv::Scalar(v);
         FaceOrientationFromString(text, v.where, &c->orientation);
       },
       [](const C& c) { return FaceOrientationToString(c.orientation); }},
      {{"boundary_y", "a number", "y level: upper at and above, lower below (none: found from the frames)"},
       [](const Value& v, C* c) {
         // Nothing (YAML null, or "" from a flag) clears it: the level is then found.
         c->has_boundary_y = !(v.kind == Value::kNull || (v.kind == Value::kScalar && v.text.empty()));
         if (c->has_boundary_y) c->options.boundary.y_level = cv::NumberOf(v, cv::Scalar(v));
       },
       [](const C& c) { return c.has_boundary_y ? cv::Text(c.options.boundary.y_level) : std::string(); }},
      {{"boundary_polygon", "a polygon file (x y per line)", "inside = lower"},
       [](const Value& v, C* c) { c->boundary_polygon = cv::Path(v, false); },
       [](const C& c) { return c.boundary_polygon; }},
      {{"boundary_margin", "a number >= 0", "drop points this close to the boundary"},
       [](const Value& v, C* c) { c->options.boundary.margin = cv::Number(v, 0, 1e300); },
       [](const C& c) { return cv::Text(c.options.boundary.margin); }},
      {{"path_point", "[x, y, z] in data units",
        "the point whose path is reported (reference frame); default: the lowest lower-part point"},
       [](const Value& v, C* c) {
         const std::array<double, 3> p = cv::Vector3(v);
         c->options.path_point = Eigen::Vector3d(p[0], p[1], p[2]);
       },
       [](const C& c) {
         if (!c.options.path_point) return std::string();
         const Eigen::Vector3d& p = *c.options.path_point;
         return cv::Text(std::array<double, 3>{p.x(), p.y(), p.z()});
       }},
      {{"cost", "one of axial, volume", "axial: trimmed least squares; volume: then L-BFGS on rho_d"},
       [](const Value& v, C* c) { c->options.cost = cv::Choice(v, kCosts); },
       [](const C& c) { return cv::NameOf(c.options.cost, kCosts); }},
      {{"trim_fraction", "a number in [0, 0.5)", "largest residuals dropped per step"},
       [](const Value& v, C* c) { c->options.trim_fraction = cv::Number(v, 0, 0.5, "[)"); },
       [](const C& c) { return cv::Text(c.options.trim_fraction); }},
      {{"max_iterations", "an integer >= 1", "solver iterations per part and frame"},
       [](const Value& v, C* c) { c->options.max_iterations = cv::Integer(v, 1); },
       [](const C& c) { return std::to_string(c.options.max_iterations); }},
      {{"step_tolerance", "a number > 0", "converged after a step shorter than this (data units)"},
       [](const Value& v, C* c) { c->options.step_tolerance = cv::Number(v, 0, 1e300, "(]"); },
       [](const C& c) { return cv::Text(c.options.step_tolerance); }},
      {{"volume_iterations", "an integer >= 0", "cost volume: L-BFGS iterations after the axial solve"},
       [](const Value& v, C* c) { c->options.volume_iterations = cv::Integer(v, 0); },
       [](const C& c) { return std::to_string(c.options.volume_iterations); }},
      {{"normal_distance", "true or false", "weight gaps by cos(slope): distance along the normal"},
       [](const Value& v, C* c) { c->options.normal_distance = cv::Boolean(v); },
       [](const C& c) { return cv::Text(c.options.normal_distance); }},
      {{"predict", "true or false", "warm start by constant-velocity extrapolation"},
       [](const Value& v, C* c) { c->options.predict = cv::Boolean(v); },
       [](const C& c) { return cv::Text(c.options.predict); }},
      {{"max_fold_fraction", "a number in [0, 1]", "area share of a part's triangles that may fold"},
       [](const Value& v, C* c) { c->options.max_fold_fraction = cv::Number(v, 0, 1); },
       [](const C& c) { return cv::Text(c.options.max_fold_fraction); }},
      {{"threads", cv::kThreadsType, "threads (all: every core)"},
       [](const Value& v, C* c) { c->options.num_threads = cv::ThreadCount(v, 256); },
       [](const C& c) { return cv::ThreadText(c.options.num_threads); }},
      {{"min_part_points", "an integer >= 3", "fewest points a part may have"},
       [](const Value& v, C* c) { c->options.min_part_points = cv::Integer(v, 3); },
       [](const C& c) { return std::to_string(c.options.min_part_points); }},
      {{"output_csv", "a file name", "per-frame CSV"},
       [](const Value& v, C* c) { c->output_csv = cv::Path(v, false); },
       [](const C& c) { return c.output_csv; }},
      {{"output_json", "a file name", "per-frame 4x4 matrices and details"},
       [](const Value& v, C* c) { c->output_json = cv::Path(v, false); },
       [](const C& c) { return c.output_json; }},
      {{"plot", "a .png file name", "the six motion parameters over the frames"},
       [](const Value& v, C* c) { c->plot = cv::Path(v, false); },
       [](const C& c) { return c.plot; }},
      {{"path_plot", "a .png file name", "the path point's displacement: sagittal (z, y) and frontal (x, y)"},
       [](const Value& v, C* c) { c->path_plot = cv::Path(v, false); },
       [](const C& c) { return c.path_plot; }},
      {{"progress", "true or false", "one line per frame on stderr"},
       [](const Value& v, C* c) { c->progress = cv::Boolean(v); },
       [](const C& c) { return cv::Text(c.progress); }},
  });
  return table;
}

bool IsSurfaceFile(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  for (const char* known : {".xyz", ".txt", ".csv", ".ply", ".off", ".obj"}) {
    if (ext == known) return true;
  }
  return false;
}

void ListFrames(JawConfig* config) {
  const std::string where = config->Where("frames");
  if (config->frames.empty()) throw InputError(where + ": required (a folder or a list of surface files)");
  namespace fs = std::filesystem;
  std::error_code error;
  config->frame_files.clear();
  if (config->frames.size() == 1 && fs::is_directory(config->frames[0], error)) {
    for (const fs::directory_entry& entry : fs::directory_iterator(config->frames[0], error)) {
      if (entry.is_regular_file(error) && IsSurfaceFile(entry.path())) {
        config->frame_files.push_back(entry.path().string());
      }
    }
    if (error) throw InputError(where + ": cannot list folder '" + config->frames[0] + "': " + error.message());
    std::sort(config->frame_files.begin(), config->frame_files.end());
    if (config->frame_files.empty()) {
      throw InputError(where + ": folder '" + config->frames[0] +
                       "' has no surface files (.xyz .txt .csv .ply .off .obj)");
    }
  } else {
    for (const std::string& file : config->frames) {
      if (!fs::is_regular_file(file, error)) throw InputError(where + ": no such file '" + file + "'");
      config->frame_files.push_back(file);
    }
  }
  if (config->frame_files.size() < 2) {
    throw InputError(where + ": a sequence needs at least 2 frames, got " +
                     std::to_string(config->frame_files.size()));
  }
}

void ResolveReference(JawConfig* config) {
  const std::string& text = config->reference;
  const bool digits = !text.empty() && std::all_of(text.begin(), text.end(), [](char c) {
    return std::isdigit(static_cast<unsigned char>(c));
  });
  const int count = static_cast<int>(config->frame_files.size());
  if (digits) {
    const long index = text.size() > 9 ? count : std::stol(text);
    if (index >= count) {
      throw InputError(config->Where("reference") + ": frame " + text + " is beyond the " +
                       std::to_string(count) + " frames (0-based)");
    }
    config->reference_index = static_cast<int>(index);
    return;
  }
  for (int k = 0; k < count; ++k) {
    if (SameFile(text, config->frame_files[k])) {
      config->reference_index = k;
      return;
    }
  }
  throw InputError(config->Where("reference") + ": '" + text + "' is neither a frame index nor one of the " +
                   std::to_string(count) + " frame files");
}

void CheckOutputs(JawConfig* config) {
  std::vector<std::pair<std::string, std::string>> outputs;  // key, path
  for (const char* key : {"output_csv", "output_json", "plot", "path_plot"}) {
    const std::string path = JawConfigValue(*config, key);
    if (path.empty()) continue;
    const std::string where = config->Where(key);
    CheckOutputPath(path, where);
    if (std::string(key) == "plot" || std::string(key) == "path_plot") {
      std::string ext = std::filesystem::path(path).extension().string();
      for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
      if (ext != ".png") throw InputError(where + ": expects a .png file name, got '" + path + "'");
      RequirePngFigures(where);
    }
    for (const std::string& frame : config->frame_files) {
      if (SameFile(path, frame)) throw InputError(where + ": '" + path + "' is one of the frames");
    }
    for (const auto& [other_key, other] : outputs) {
      if (SameFile(path, other)) throw InputError(where + ": '" + path + "' is also " + other_key);
    }
    outputs.emplace_back(key, path);
  }
}

}  // namespace

FaceFrameOptions JawConfig::AsIsOrientation() {
  FaceFrameOptions options;
  options.orientation = FaceOrientation::kAsIs;
  return options;
}

std::string JawConfig::Where(const std::string& key) const {
  const auto found = origin.find(key);
  if (found != origin.end()) return found->second;
  // A key never given: name the config file it is missing from, if any.
  return (config_file.empty() ? "" : config_file + ": ") + "key '" + key + "'";
}

const std::vector<JawConfigKey>& JawConfigKeys() { return Table().keys(); }

std::string JawConfigValue(const JawConfig& config, const std::string& key) { return Table().Get(config, key); }

void ApplyJawYaml(const std::string& yaml_text, const std::string& file, JawConfig* config) {
  Table().ApplyYaml(yaml_text, file, config);
}

void ApplyJawConfigFile(const std::string& path, JawConfig* config) { Table().ApplyFile(path, config); }

void ApplyJawFlag(const std::string& key, const std::string& value, JawConfig* config) {
  Table().ApplyFlag(key, value, config);
}

void FinishJawConfig(JawConfig* config) {
  ListFrames(config);
  ResolveReference(config);
  config->options.reference = config->reference_index;
  const bool polygon = !config->boundary_polygon.empty();
  if (polygon && config->has_boundary_y) {
    throw InputError(config->Where("boundary_polygon") + ": give either boundary_y or boundary_polygon, not both");
  }
  config->options.find_boundary = !polygon && !config->has_boundary_y;
  config->options.boundary.polygon.clear();
  if (polygon) {
    try {
      config->options.boundary.polygon = ReadPolygon(config->boundary_polygon);
    } catch (const InputError& e) {
      throw InputError(config->Where("boundary_polygon") + ": " + e.what());
    }
  }
  CheckOutputs(config);
  std::string error;
  if (!config->options.IsValid(&error)) throw InputError("jaw settings: " + error);
}

}  // namespace surfreg
