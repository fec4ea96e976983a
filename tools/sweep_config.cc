#include "tools/sweep_config.h"

#include <yaml-cpp/yaml.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <map>
#include <set>

#include "measure/input_error.h"
#include "io/surface_reader_internal.h"
#include "tools/config_value.h"

namespace surfreg {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Where a node is: "FILE:LINE".
std::string At(const std::string& file, const YAML::Node& node) {
  const YAML::Mark mark = node.Mark();
  return file + (mark.is_null() ? "" : ":" + std::to_string(mark.line + 1));
}

// "FILE:LINE: key 'NAME'".
std::string Where(const std::string& file, const YAML::Node& node, const std::string& name) {
  return At(file, node) + ": key '" + name + "'";
}

// "WHERE expects ...", as align's messages; "WHERE: what" otherwise.
[[noreturn]] void Fail(const std::string& where, const std::string& what) {
  throw InputError(where + (what.rfind("expects ", 0) == 0 ? " " : ": ") + what);
}

std::string Shown(const YAML::Node& node) {
  if (node.IsScalar()) return io_internal::Quote(node.Scalar());
  if (node.IsSequence()) return "a list";
  if (node.IsMap()) return "a mapping";
  return "nothing";
}

double Number(const YAML::Node& node, const std::string& where, const char* expected) {
  double value = 0;
  if (!node.IsScalar() ||
      io_internal::ParseNumber(node.Scalar(), &value) != io_internal::NumberStatus::kOk ||
      !std::isfinite(value)) {
    Fail(where, std::string("expects ") + expected + ", got " + Shown(node));
  }
  return value;
}

template <typename Int>
Int Integer(const YAML::Node& node, const std::string& where, Int lo, const char* expected) {
  Int value = 0;
  const std::string text = node.IsScalar() ? node.Scalar() : "";
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (text.empty() || error != std::errc() || end != text.data() + text.size() || value < lo) {
    Fail(where, std::string("expects ") + expected + ", got " + Shown(node));
  }
  return value;
}

std::string Text(const YAML::Node& node, const std::string& where, const char* expected) {
  if (!node.IsScalar() || node.Scalar().empty()) {
    Fail(where, std::string("expects ") + expected + ", got " + Shown(node));
  }
  return node.Scalar();
}

// A number or a list of numbers, each >= 0.
std::vector<double> Magnitudes(const YAML::Node& node, const std::string& where) {
  const char* expected = "a number >= 0 or a non-empty list of them";
  std::vector<double> out;
  if (node.IsSequence()) {
    for (const YAML::Node& item : node) out.push_back(Number(item, where, expected));
  } else {
    out.push_back(Number(node, where, expected));
  }
  if (out.empty() || std::any_of(out.begin(), out.end(), [](double v) { return v < 0; })) {
    Fail(where, std::string("expects ") + expected);
  }
  return out;
}

// Checks the keys of mapping `node` against `known` (file order, no repeats)
// and returns key name → (key node, value node).
using Entries = std::map<std::string, std::pair<YAML::Node, YAML::Node>>;
Entries Mapping(const YAML::Node& node, const std::string& file, const std::string& prefix,
                const std::vector<std::string>& known) {
  Entries entries;
  for (const auto& pair : node) {
    const std::string name = pair.first.IsScalar() ? pair.first.Scalar() : "?";
    const std::string where = Where(file, pair.first, prefix + name);
    if (!pair.first.IsScalar()) Fail(where, "expected a key name, found a list or mapping");
    if (!known.empty() && std::find(known.begin(), known.end(), name) == known.end()) {
      std::string best, list;
      std::size_t best_distance = std::max<std::size_t>(2, name.size() / 3) + 1;
      for (const std::string& k : known) {
        list += (list.empty() ? "" : ", ") + k;
        const std::size_t distance = config_value::EditDistance(name, k);
        if (distance < best_distance) best_distance = distance, best = k;
      }
      std::string hint =
          best.empty() ? " (known keys: " + list + ")" : " (did you mean '" + best + "'?)";
      if (prefix.empty() && !NearestAlignKey(name).empty() && best.empty()) {
        hint = " (align settings go under 'settings:' or, with lists of values, 'sweep:')";
      }
      Fail(At(file, pair.first), "unknown key " + io_internal::Quote(prefix + name) + hint);
    }
    if (!entries.emplace(name, std::make_pair(pair.first, pair.second)).second) {
      Fail(where, "given twice (also at line " +
                      std::to_string(entries.at(name).first.Mark().line + 1) + ")");
    }
  }
  return entries;
}

YAML::Node RequireMap(const YAML::Node& node, const std::string& where) {
  if (!node.IsMap()) Fail(where, "expects a mapping of 'key: value' lines, got " + Shown(node));
  return node;
}

// A setting's value as the text ApplyAlignFlag reads: a scalar, "[a, b]"
// for a list of scalars, "" for nothing.
std::string SettingText(const YAML::Node& node, const std::string& where) {
  if (node.IsNull()) return "";
  if (node.IsScalar()) return node.Scalar();
  if (node.IsSequence()) {
    std::string out;
    for (const YAML::Node& item : node) {
      if (!item.IsScalar()) Fail(where, "expects a value or a list of values, got a nested list");
      out += (out.empty() ? "" : ", ") + item.Scalar();
    }
    return "[" + out + "]";
  }
  Fail(where, "expects a value, got a mapping");
}

// Keys that are not settings of a sweep, and why.
const char* NotASetting(const std::string& key) {
  if (key == "reference" || key == "moving") return "the surfaces are given under 'pairs:'";
  if (key == "output" || key == "matrix_txt" || key == "aligned" || key == "log") {
    return "a sweep writes no per-run files ('output:' at the top names the CSV)";
  }
  if (key == "initial_rotation_deg" || key == "initial_translation" ||
      key == "initial_transform") {
    return "the starts are set by the truth and 'perturbations:'";
  }
  if (key == "threads") return "runs are parallel, each on one thread (use 'jobs:')";
  if (key == "progress") return "a sweep shows its own progress bar";
  if (IsTerrainKey(key)) return "terrain inputs and change outputs are for single 'surfreg align' runs";
  return nullptr;
}

// Applies `text` to `config` for `key`; messages start with `where`
// instead of align's "flag '--KEY'".
void ApplySetting(const std::string& key, const std::string& text, const std::string& where,
                  AlignConfig* config) {
  if (const char* why = NotASetting(key)) Fail(where, std::string("not a sweep setting: ") + why);
  try {
    ApplyAlignFlag(key, text, config);
  } catch (const InputError& e) {
    std::string message = e.what();
    const std::string flag = "flag '--" + key + "'";
    if (message.rfind(flag, 0) == 0) message = message.substr(flag.size());
    message.erase(0, message.find_first_not_of(": "));
    Fail(where, message);
  }
  config->origin[key] = where;
}

Eigen::Matrix4d MatrixFromNode(const YAML::Node& node, const std::string& where) {
  const char* expected = "4 rows of 4 numbers (a rigid motion, moving -> reference)";
  std::vector<double> values;
  if (!node.IsSequence()) Fail(where, std::string("expects ") + expected + ", got " + Shown(node));
  for (const YAML::Node& row : node) {
    if (row.IsSequence()) {
      for (const YAML::Node& item : row) values.push_back(Number(item, where, expected));
    } else {
      values.push_back(Number(row, where, expected));
    }
  }
  if (values.size() != 16) Fail(where, std::string("expects ") + expected);
  Eigen::Matrix4d m;
  for (int i = 0; i < 16; ++i) m(i / 4, i % 4) = values[i];
  const Eigen::Matrix3d r = m.topLeftCorner<3, 3>();
  const bool rigid =
      (r.transpose() * r - Eigen::Matrix3d::Identity()).norm() < 1e-6 && r.determinant() > 0 &&
      std::fabs(m(3, 0)) + std::fabs(m(3, 1)) + std::fabs(m(3, 2)) + std::fabs(m(3, 3) - 1) < 1e-9;
  if (!rigid)
    Fail(where, "is not a rigid motion (rotation part not orthonormal, or last row not 0 0 0 1)");
  return m;
}

std::array<double, 3> Vector3(const YAML::Node& node, const std::string& where) {
  const char* expected = "a list of 3 numbers";
  if (!node.IsSequence() || node.size() != 3) {
    Fail(where, std::string("expects ") + expected + ", got " + Shown(node));
  }
  return {Number(node[0], where, expected), Number(node[1], where, expected),
          Number(node[2], where, expected)};
}

SweepTruth ParseTruth(const YAML::Node& node, const std::string& file, const std::string& name) {
  RequireMap(node, Where(file, node, name));
  const Entries e =
      Mapping(node, file, name + ".", {"rotation_deg", "translation", "matrix", "file"});
  SweepTruth truth;
  const bool about_centroid = e.count("rotation_deg") || e.count("translation");
  if (int(about_centroid) + int(e.count("matrix")) + int(e.count("file")) != 1) {
    Fail(Where(file, node, name),
         "give one of {rotation_deg, translation} (about the moving centroid), matrix, or file");
  }
  if (about_centroid) {
    truth.kind = SweepTruth::Kind::kAboutCentroid;
    for (const char* key : {"rotation_deg", "translation"}) {
      if (!e.count(key)) continue;
      const auto& [k, v] = e.at(key);
      (std::string(key) == "rotation_deg" ? truth.rotation_deg : truth.translation) =
          Vector3(v, Where(file, k, name + "." + key));
    }
  } else if (e.count("matrix")) {
    truth.kind = SweepTruth::Kind::kMatrix;
    truth.matrix =
        MatrixFromNode(e.at("matrix").second, Where(file, e.at("matrix").first, name + ".matrix"));
  } else {
    const auto& [k, v] = e.at("file");
    const std::string where = Where(file, k, name + ".file");
    const std::string path = Text(v, where, "a transform JSON file (written by surfreg align)");
    YAML::Node json;
    try {
      json = YAML::Load(io_internal::ReadFile(path));  // JSON is YAML
    } catch (const YAML::Exception& ex) {
      Fail(where, "'" + path + "' is not valid JSON: " + ex.msg);
    } catch (const InputError& ex) {
      Fail(where, ex.what());
    }
    if (!json.IsMap() || !json["matrix"]) Fail(where, "'" + path + "' has no \"matrix\"");
    truth.kind = SweepTruth::Kind::kMatrix;
    truth.matrix = MatrixFromNode(json["matrix"], where + ": '" + path + "' \"matrix\"");
  }
  return truth;
}

bool GoodName(const std::string& name) {
  return !name.empty() && std::all_of(name.begin(), name.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.';
  });
}

void ParsePairs(const YAML::Node& key, const YAML::Node& node, SweepConfig* config) {
  const std::string& file = config->file;
  if (!node.IsSequence() || node.size() == 0) {
    Fail(Where(file, key, "pairs"),
         "expects a list of pairs (each with reference and moving), got " + Shown(node));
  }
  std::set<std::string> names;
  for (std::size_t i = 0; i < node.size(); ++i) {
    const std::string name = "pairs[" + std::to_string(i + 1) + "]";
    SweepPair pair;
    pair.where = Where(file, node[i], name);
    RequireMap(node[i], pair.where);
    const Entries e = Mapping(node[i], file, name + ".", {"name", "reference", "moving", "truth"});
    for (const char* required : {"reference", "moving"}) {
      if (!e.count(required)) Fail(pair.where, std::string("has no '") + required + ": FILE'");
    }
    pair.reference =
        Text(e.at("reference").second, Where(file, e.at("reference").first, name + ".reference"),
             "a surface file");
    pair.moving = Text(e.at("moving").second, Where(file, e.at("moving").first, name + ".moving"),
                       "a surface file");
    pair.name = "pair" + std::to_string(i + 1);
    if (e.count("name")) {
      const std::string where = Where(file, e.at("name").first, name + ".name");
      pair.name = Text(e.at("name").second, where, "a name of letters, digits, '_', '-', '.'");
      if (!GoodName(pair.name))
        Fail(where, "expects a name of letters, digits, '_', '-', '.', got " +
                        io_internal::Quote(pair.name));
    }
    if (!names.insert(pair.name).second)
      Fail(pair.where, "the name '" + pair.name + "' is used twice");
    if (e.count("truth")) pair.truth = ParseTruth(e.at("truth").second, file, name + ".truth");
    config->pairs.push_back(pair);
  }
}

void ParseSettings(const YAML::Node& key, const YAML::Node& node, SweepConfig* config) {
  RequireMap(node, Where(config->file, key, "settings"));
  for (const auto& [name, entry] : Mapping(node, config->file, "settings.", {})) {
    const std::string where = Where(config->file, entry.first, "settings." + name);
    ApplySetting(name, SettingText(entry.second, where), where, &config->base);
  }
}

// In file order (the grid order), each value checked on a copy of the base.
void ParseSweep(const YAML::Node& key, const YAML::Node& node, SweepConfig* config) {
  RequireMap(node, Where(config->file, key, "sweep"));
  Mapping(node, config->file, "sweep.", {});  // names and repeats
  for (const auto& entry : node) {
    const std::string name = entry.first.Scalar();
    SweptKey swept;
    swept.key = name;
    swept.where = Where(config->file, entry.first, "sweep." + name);
    if (name == "classes" || name == "columns") {
      Fail(swept.where, "cannot be swept: it decides how the pairs are read (once); set it under 'settings:'");
    }
    if (config->base.origin.count(name)) {
      Fail(swept.where, "is also set under 'settings:' (" + config->base.origin.at(name) + ")");
    }
    if (!entry.second.IsSequence() || entry.second.size() == 0) {
      Fail(swept.where, "expects a non-empty list of values to sweep, got " + Shown(entry.second));
    }
    for (std::size_t i = 0; i < entry.second.size(); ++i) {
      const std::string where = swept.where + " value " + std::to_string(i + 1);
      swept.values.push_back(SettingText(entry.second[i], where));
      AlignConfig scratch = config->base;
      ApplySetting(name, swept.values.back(), where, &scratch);
      swept.values.back() = AlignConfigValue(scratch, name);  // canonical text
    }
    config->swept.push_back(swept);
  }
}

void ParsePerturbations(const YAML::Node& key, const YAML::Node& node, SweepConfig* config) {
  const std::string& file = config->file;
  RequireMap(node, Where(file, key, "perturbations"));
  const Entries e = Mapping(node, file, "perturbations.",
                            {"rotation_deg", "shift_spacings", "directions", "seed"});
  const auto where = [&](const char* k) {
    return Where(file, e.at(k).first, std::string("perturbations.") + k);
  };
  if (e.count("rotation_deg"))
    config->rotation_deg = Magnitudes(e.at("rotation_deg").second, where("rotation_deg"));
  if (e.count("shift_spacings"))
    config->shift_spacings = Magnitudes(e.at("shift_spacings").second, where("shift_spacings"));
  std::vector<double>& a = config->rotation_deg;
  std::vector<double>& s = config->shift_spacings;
  if (a.size() == 1) a.resize(s.size(), a[0]);
  if (s.size() == 1) s.resize(a.size(), s[0]);
  if (a.size() != s.size()) {
    Fail(Where(file, key, "perturbations"),
         "rotation_deg and shift_spacings are paired level by level: give lists of equal length "
         "(or one value)");
  }
  if (std::any_of(a.begin(), a.end(), [](double v) { return v > 180; })) {
    Fail(where("rotation_deg"), "expects angles of at most 180 degrees");
  }
  if (e.count("directions"))
    config->directions =
        Integer<int>(e.at("directions").second, where("directions"), 1, "an integer >= 1");
  if (e.count("seed"))
    config->seed = Integer<uint64_t>(e.at("seed").second, where("seed"), 0, "an integer >= 0");
}

void ParseSuccess(const YAML::Node& key, const YAML::Node& node, SweepConfig* config) {
  RequireMap(node, Where(config->file, key, "success"));
  const Entries e = Mapping(node, config->file, "success.", {"rotation_deg", "spacings"});
  for (const char* k : {"rotation_deg", "spacings"}) {
    if (!e.count(k)) continue;
    const std::string where = Where(config->file, e.at(k).first, std::string("success.") + k);
    const double value = Number(e.at(k).second, where, "a number > 0");
    if (!(value > 0)) Fail(where, "expects a number > 0, got " + Shown(e.at(k).second));
    (std::string(k) == "rotation_deg" ? config->success_rotation_deg : config->success_spacings) =
        value;
  }
}

}  // namespace

Eigen::Matrix4d TruthMatrix(const SweepTruth& truth, const Eigen::Vector3d& c) {
  if (truth.kind == SweepTruth::Kind::kMatrix) return truth.matrix;
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  if (truth.kind == SweepTruth::Kind::kNone) return m;
  const Eigen::Vector3d w(truth.rotation_deg[0], truth.rotation_deg[1], truth.rotation_deg[2]);
  const double angle = w.norm() * kPi / 180;
  const Eigen::Matrix3d r =
      angle > 0 ? Eigen::AngleAxisd(angle, w.normalized()).matrix() : Eigen::Matrix3d::Identity();
  const Eigen::Vector3d t(truth.translation[0], truth.translation[1], truth.translation[2]);
  m.topLeftCorner<3, 3>() = r;
  m.topRightCorner<3, 1>() = c + t - r * c;
  return m;
}

SweepConfig ParseSweepConfig(const std::string& yaml_text, const std::string& file) {
  YAML::Node root;
  try {
    root = YAML::Load(yaml_text);
  } catch (const YAML::Exception& e) {
    throw InputError(file + (e.mark.is_null() ? "" : ":" + std::to_string(e.mark.line + 1)) +
                     ": not valid YAML: " + e.msg);
  }
  if (!root.IsMap()) throw InputError(file + ": expected a YAML mapping of 'key: value' lines");
  SweepConfig config;
  config.file = file;
  try {
    const Entries e =
        Mapping(root, file, "",
                {"pairs", "settings", "sweep", "perturbations", "success", "jobs", "output"});
    if (!e.count("pairs"))
      throw InputError(file + ": no 'pairs:' (a list of reference/moving surface pairs)");
    if (!e.count("output")) throw InputError(file + ": no 'output: FILE.csv' (the per-run CSV)");
    ParsePairs(e.at("pairs").first, e.at("pairs").second, &config);
    if (e.count("settings"))
      ParseSettings(e.at("settings").first, e.at("settings").second, &config);
    if (e.count("sweep")) ParseSweep(e.at("sweep").first, e.at("sweep").second, &config);
    if (e.count("perturbations"))
      ParsePerturbations(e.at("perturbations").first, e.at("perturbations").second, &config);
    if (e.count("success")) ParseSuccess(e.at("success").first, e.at("success").second, &config);
    if (e.count("jobs"))
      config.jobs = Integer<int>(e.at("jobs").second, Where(file, e.at("jobs").first, "jobs"), 1,
                                 "an integer >= 1");
    const std::string where = Where(file, e.at("output").first, "output");
    config.output = Text(e.at("output").second, where, "a file name ending in .csv");
    if (config.output.size() < 5 || config.output.substr(config.output.size() - 4) != ".csv") {
      Fail(where, "expects a file name ending in .csv, got " + io_internal::Quote(config.output));
    }
    config.output_where = where;
  } catch (const YAML::Exception& e) {  // not expected once parsed; kept one line all the same
    throw InputError(file + ": " + e.msg);
  }
  return config;
}

SweepConfig ReadSweepConfig(const std::string& path) {
  std::string text;
  try {
    text = io_internal::ReadFile(path);
  } catch (const InputError& e) {
    throw InputError(std::string("flag '--config': ") + e.what());
  }
  return ParseSweepConfig(text, path);
}

}  // namespace surfreg
