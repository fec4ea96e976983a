// The `surfreg` program: a thin dispatcher over subcommands (tools/commands.h).
//
// Exit codes: 0 ok; 2 bad input or bad usage (one "surfreg: error: ..." line
// on stderr, plus a usage line for usage errors); 1 internal error; 130 / 143
// interrupted by SIGINT / SIGTERM ("surfreg: interrupted"; io/interrupt.h);
// align: 3 when the verdict is "failed" (its outputs are still written).
#include <gflags/gflags.h>
#include <glog/logging.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <cstdio>
#include <cstring>
#include <exception>
#include <string>
#include <vector>

#include "measure/input_error.h"
#include "tools/align_config.h"
#include "tools/cli_help.h"
#include "tools/commands.h"
#include "tools/measure_run.h"
#include "io/interrupt.h"
#include "tools/jaw_config.h"
#include "tools/key_flags.h"
#include "tools/log_prefix.h"
#include "tools/series_config.h"
#include "measure/tasks.h"

namespace surfreg {
namespace {

struct Command {
  const char* name;
  int (*run)(const std::vector<std::string>& args);
  const char* synopsis;  // the arguments, for usage lines
  const char* help;      // one line
  // The program's flags this command reads (space-separated), besides its
  // config keys' flags (`keys`, if any); any other flag of the program is
  // refused, so that e.g. `align --weights=...` is not silently ignored.
  const char* flags;
  bool (*keys)(const std::string& name);
};

bool IsAlignKey(const std::string& name) {
  for (const AlignConfigKey& key : AlignConfigKeys()) {
    if (name == key.name) return true;
  }
  return false;
}

bool IsMeasureKey(const std::string& name) {
  const std::vector<std::string>& keys = MeasureKeys();
  return std::find(keys.begin(), keys.end(), name) != keys.end();
}

bool IsJawKey(const std::string& name) {
  for (const JawConfigKey& key : JawConfigKeys()) {
    if (name == key.name) return true;
  }
  return false;
}

bool IsSeriesKey(const std::string& name) {
  for (const ConfigKey& key : SeriesConfigKeys()) {
    if (name == key.name) return true;
  }
  return false;
}

const Command kCommands[] = {
    {"triangulate", RunTriangulate, "FILE [--domain=data|hull] [--threads=N|all] [--json]",
     "read a surface, Delaunay-triangulate it, print counts, its data domain and timings",
     "json domain domain_max_edge_spacings domain_min_thinness threads", nullptr},
    {"measure", RunMeasure,
     "A B [--volume=overlay|union] [--weights=uniform|per_point|mask:FILE] "
     "[--mask_mode=include|exclude] [--mask_layer=NAME] [--domain=data|hull] [--min_overlap_fraction=F] [--lod=L] "
     "[--reference_crs=CRS] [--moving_crs=CRS] "
     "[--frame=auto|enu|utm] [--band=N] [--window=C,R,W,H] [--sigma_reference=S|RASTER] "
     "[--sigma_moving=S|RASTER] [--lod_confidence=C] [--error_model=independent|correlated|variogram] "
     "[--variogram_png=FILE.png] [--change_mask=FILE] [--dod_sigma=S.tif] [--classes=C,...] [--columns=X,Y,Z] "
     "[--tile=N | --max_memory=SIZE] [--shard=K/N --partial=P.json] [--resume] [--dod=DOD.tif] "
     "[--json] [--quiet]",
     "compare surface B with A in one metric frame: volume between them (rho_d), mean gap, "
     "cut/fill (with propagated uncertainty when each DEM's sigma is given, or with the DoD's "
     "spatially correlated errors estimated from the data), timings",
     "json quiet shard partial resume", IsMeasureKey},
    {"align", RunAlign,
     "(--config FILE.yaml | REFERENCE MOVING) [--KEY=VALUE for any config key] [--json] [--quiet]",
     "rigidly move MOVING onto REFERENCE; write the transform JSON, print a summary",
     "config json manifest shard quiet", IsAlignKey},
    {"series", RunSeries,
     "(--config FILE.yaml | E0 E1 ...) [--reference=K] [--pairs=0-1,...] [--min_overlap=F] [--output=S.json] "
     "[--aligned_dir=DIR] [--dod_dir=DIR] [--KEY=VALUE for align's alignment keys] [--json] [--quiet]",
     "align a series of surveys jointly: one motion per epoch into the reference epoch's frame, "
     "over every pair that overlaps",
     "config json quiet", IsSeriesKey},
    {"sweep", RunSweep, "--config SWEEP.yaml [--output=RUNS.csv] [--jobs=N] [--shard=K/N] [--resume] [--quiet]",
     "run a grid of pairs x solver settings x initial offsets; CSV, ranking, plots",
     "config output jobs shard resume quiet", nullptr},
    {"normalize", RunNormalize,
     "MESH [--orientation=auto|as_is|RX,RY,RZ] [--depth_limit=D] [--output=FACE.xyz] [--json]",
     "bring a face mesh or cloud into the standard face frame; write its visible height field",
     "orientation depth_limit output json", nullptr},
    {"asymmetry", RunAsymmetry,
     "FACE | FOLDER | SCAN1 SCAN2 [--orientation=auto|as_is|RX,RY,RZ] [--depth_limit=D] "
     "[--regions=NAME:FILE,...] [--map=MAP.png] [--points=D.csv|.ply] [--csv=TABLE.csv] [--norms=COHORT.csv] "
     "[--units=mm] [--threads=N|all] [--json] [--output=ASYMMETRY.json] [--quiet]",
     "facial asymmetry: the face against its mirror image about the optimized plane; indices by region "
     "(thirds, halves, yours) with sigma; a folder is a cohort (a table row per face), two scans a test-retest",
     "orientation depth_limit regions map points csv norms units threads output json quiet", nullptr},
    {"jaw", RunJaw, "--config JAW.yaml [--KEY=VALUE ...] [--quiet]",
     "jaw motion over a 3D sequence: the lower part relative to the upper part, per frame",
     "config quiet", IsJawKey},
    {"transform", RunTransform,
     "INPUT --transform=T.json|T.txt --output=OUT [--inverse] [--grid=REF.tif] [--classes=C,...] "
     "[--columns=X,Y,Z] [--band=N] [--window=C,R,W,H] [--threads=N|all] [--quiet]",
     "apply a rigid transform (align's JSON or a 4x4 text matrix) to a cloud or raster; write "
     "a cloud, or a GeoTIFF on the input's grid or REF's",
     "transform output inverse grid classes columns band window threads quiet", nullptr},
    {"merge", RunMerge, "OUT.csv IN.csv [IN.csv ...] | OUT.json PART.json [PART.json ...] [--dod=DOD.tif] [--json]",
     "join the CSVs of sweep or align --manifest shards, sorted by run_id; or the partial "
     "results of a tiled measure's shards into its report (and DoD)", "dod json", nullptr},
};

const Command* FindCommand(const std::string& name) {
  for (const Command& command : kCommands) {
    if (name == command.name) return &command;
  }
  return nullptr;
}

std::string Usage() {
  std::string text =
      "usage: surfreg <command> [arguments] [flags]\n\n"
      "Compares and aligns height-field surfaces z = F(x, y).\n"
      "Surface files: .xyz .txt .csv .ply .off .obj .las, and GDAL rasters (.tif .asc ...)\n\n"
      "commands:\n";
  for (const Command& command : kCommands) {
    text += "  " + std::string(command.name) + " " + command.synopsis + "\n      " + command.help +
            "\n";
  }
  text += "  help [command]\n      print this text, or one command's usage\n";
  return text;
}

std::string CommandNames() {
  std::string names;
  for (const Command& command : kCommands) names += (names.empty() ? "" : ", ") + std::string(command.name);
  return names;
}

// "unknown command 'aling' (did you mean 'align'?)", else the list.
std::string UnknownCommand(const std::string& name) {
  std::vector<std::string> names;
  for (const Command& command : kCommands) names.push_back(command.name);
  const std::string nearest = NearestKey(name, names);
  return "unknown command '" + name + "' (" +
         (nearest.empty() ? "commands: " + CommandNames() : "did you mean '" + nearest + "'?") + ")";
}

// The program's own flags (defined under tools/), for suggestions.
bool OwnFlag(const gflags::CommandLineFlagInfo& info) {
  return info.filename.rfind("tools/", 0) == 0 || info.filename.find("/tools/") != std::string::npos;
}

std::string UnknownFlag(const std::string& arg, const std::string& name) {
  std::vector<gflags::CommandLineFlagInfo> flags;
  gflags::GetAllFlags(&flags);
  std::vector<std::string> names;
  for (const gflags::CommandLineFlagInfo& info : flags) {
    if (OwnFlag(info)) names.push_back(info.name);
  }
  return "unknown flag '" + arg + "'" + UnknownKeyHint(name, names, "--");
}

std::string CommandUsage(const Command& command) {
  return "usage: surfreg " + std::string(command.name) + " " + command.synopsis;
}

// Messages are one line by contract; this keeps it so for any what().
std::string OneLine(std::string text) {
  for (char& c : text) {
    if (c == '\n' || c == '\r') c = ' ';
  }
  return text;
}

bool IsHelpFlag(const std::string& arg) {
  return arg == "--help" || arg == "-help" || arg == "-h" || arg == "--h" || arg == "-?";
}

// gflags would exit(1) itself on an unknown flag or a bad value; checking
// first keeps such mistakes usage errors (exit 2). SetCommandLineOption both
// validates and sets, as the parse that follows would. Returns the names of
// the flags given (a negated bool by its own name).
std::vector<std::string> CheckFlags(int argc, char** argv) {
  std::vector<std::string> given;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--") return given;
    if (arg.size() < 2 || arg[0] != '-') continue;
    const std::size_t dashes = arg[1] == '-' ? 2 : 1;
    const std::size_t equals = arg.find('=');
    std::string name = arg.substr(dashes, equals == std::string::npos ? equals : equals - dashes);
    gflags::CommandLineFlagInfo info;
    const bool known = gflags::GetCommandLineFlagInfo(name.c_str(), &info);
    if (!known) {
      const bool negated_bool = name.rfind("no", 0) == 0 &&
                                gflags::GetCommandLineFlagInfo(name.c_str() + 2, &info) &&
                                info.type == "bool" && equals == std::string::npos;
      if (negated_bool) {
        given.push_back(name.substr(2));
        continue;
      }
      throw UsageError(UnknownFlag(arg, name));
    }
    given.push_back(name);
    std::string value;
    if (equals != std::string::npos) {
      value = arg.substr(equals + 1);
    } else if (info.type == "bool") {
      continue;
    } else if (i + 1 < argc) {
      value = argv[++i];
    } else {
      throw UsageError("flag '" + arg + "' needs a value");
    }
    if (gflags::SetCommandLineOption(name.c_str(), value.c_str()).empty()) {
      throw UsageError("bad value '" + value + "' for flag '--" + name + "'");
    }
  }
  return given;
}

bool ReadsFlag(const Command& command, const std::string& name) {
  const std::string list = std::string(" ") + command.flags + " ";
  if (list.find(" " + name + " ") != std::string::npos) return true;
  return command.keys != nullptr && command.keys(name);
}

// Flags of the program's own (defined under tools/) that `command` does not
// read are refused; glog's and gflags' own flags are for every command.
void CheckCommandFlags(const Command& command, const std::vector<std::string>& given) {
  for (const std::string& name : given) {
    gflags::CommandLineFlagInfo info;
    if (!gflags::GetCommandLineFlagInfo(name.c_str(), &info)) continue;
    if (!OwnFlag(info) || ReadsFlag(command, name)) continue;
    std::string users;
    for (const Command& other : kCommands) {
      if (ReadsFlag(other, name)) users += std::string(users.empty() ? "" : ", ") + other.name;
    }
    throw UsageError("flag '--" + name + "' is not used by '" + command.name + "'" +
                     (users.empty() ? "" : " (it is a flag of: " + users + ")"));
  }
}

// `surfreg help [command]`, or a help flag anywhere.
int PrintHelp(const std::vector<std::string>& positional) {
  const Command* command = positional.empty() ? nullptr : FindCommand(positional[0]);
  if (command == nullptr && !positional.empty()) {
    std::fprintf(stderr, "surfreg: error: help: %s\n", OneLine(UnknownCommand(positional[0])).c_str());
    return 2;
  }
  if (command != nullptr) {
    std::printf("%s\n  %s\n%s", CommandUsage(*command).c_str(), command->help,
                CommandKeysHelp(command->name, command->flags).c_str());
  } else {
    std::printf("%s", Usage().c_str());
  }
  return 0;
}

int Dispatch(int argc, char** argv) {
  bool help = false;
  for (int i = 1; i < argc && std::string(argv[i]) != "--"; ++i) help |= IsHelpFlag(argv[i]);
  std::vector<std::string> positional, given;
  if (!help) {
    given = CheckFlags(argc, argv);
    gflags::ParseCommandLineNonHelpFlags(&argc, &argv, /*remove_flags=*/true);
    gflags::HandleCommandLineHelpFlags();  // --helpfull, --version, ...
  }
  for (int i = 1; i < argc; ++i) {
    if (!(help && (IsHelpFlag(argv[i]) || argv[i][0] == '-'))) positional.push_back(argv[i]);
  }
  if (help) return PrintHelp(positional);
  if (positional.empty()) {
    std::fprintf(stderr, "surfreg: error: missing command\n%s", Usage().c_str());
    return 2;
  }
  const std::string name = positional[0];
  positional.erase(positional.begin());
  if (name == "help") return PrintHelp(positional);
  const Command* command = FindCommand(name);
  if (command == nullptr) {
    std::fprintf(stderr, "surfreg: error: %s\nrun 'surfreg help' for usage\n",
                 OneLine(UnknownCommand(name)).c_str());
    return 2;
  }
  try {
    CheckCommandFlags(*command, given);
    return command->run(positional);
  } catch (const UsageError& e) {
    std::fprintf(stderr, "surfreg: error: %s\n%s\n", OneLine(e.what()).c_str(),
                 CommandUsage(*command).c_str());
    return 2;
  }
}

}  // namespace

// Total wall time T, time inside parallel regions P, serial share
// s = (T − P) / T, and T_N = (T − P) + Σ region / min(N, its chunks).
void PrintRegionTiming(std::chrono::steady_clock::time_point start) {
  const double total = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const RegionTiming t = TakeRegionTiming();
  const double serial = std::max(0.0, total - t.parallel_seconds);
  std::fprintf(stderr,
               "surfreg: region timing: total %.3f s, in %lld parallel regions %.3f s, serial %.3f s (%.1f%%); "
               "projected speed-up on 2, 8, 16, 64 cores: %.2f, %.2f, %.2f, %.2f\n",
               total, static_cast<long long>(t.regions), t.parallel_seconds, serial, 100.0 * serial / total,
               total / (serial + t.projected_seconds[0]), total / (serial + t.projected_seconds[1]),
               total / (serial + t.projected_seconds[2]), total / (serial + t.projected_seconds[3]));
}

}  // namespace surfreg

int main(int argc, char** argv) {
  // Logs go to stderr, warnings and up only, so normal output stays clean;
  // --minloglevel=0 shows the INFO lines.
  FLAGS_logtostderr = true;
  FLAGS_minloglevel = google::GLOG_WARNING;
  // The optional parts this build has: scripts and tests ask --version.
  gflags::SetVersionString(std::string(SURFREG_VERSION) + " (rasters and CRSs: " +
                           (SURFREG_HAS_GDAL ? "yes" : "no, built without GDAL") + "; PNG figures: " +
                           (SURFREG_HAS_PLOTS ? "yes" : "no, built without Cairo") + ")");
  gflags::SetUsageMessage("<command> [arguments] [flags]; run 'surfreg help' for the commands");
  google::InitGoogleLogging(argv[0], &surfreg::LogPrefix);  // surfreg: warning: ...
  surfreg::RegisterKeyFlags();  // before anything reads or parses a flag
  surfreg::InstallInterruptHandlers();
  // SURFREG_REGION_TIMING=1: one stderr line at the end with the time spent
  // inside the parallel regions and the Amdahl projection (docs/speed.md,
  // Threads); meant for one-thread runs (--threads=1).
  const char* region_timing = std::getenv("SURFREG_REGION_TIMING");
  const bool timing = region_timing != nullptr && std::strcmp(region_timing, "1") == 0;
  const auto start = std::chrono::steady_clock::now();
  if (timing) surfreg::SetRegionTiming(true);
  try {
    const int code = surfreg::Dispatch(argc, argv);
    surfreg::ThrowIfInterrupted();
    if (timing) surfreg::PrintRegionTiming(start);  // a signal during a stage that does not check
    // Results printed to a full disk, a file past `ulimit -f` or a closed
    // pipe must not end as a success: the last buffered bytes are written
    // here, and any failed write of stdout is sticky in ferror.
    if (std::fflush(stdout) != 0 || std::ferror(stdout)) {
      const int error = errno;
      std::fprintf(stderr, "surfreg: error: cannot write the standard output: %s\n",
                   error != 0 ? std::strerror(error) : "write error");
      return 2;
    }
    return code;
  } catch (const surfreg::Interrupted& e) {
    // What is complete stays (outputs written, a sweep's partial file, the
    // --log rows); only the temporaries go. io/interrupt.h.
    surfreg::RemoveTemporaries();
    std::fflush(stdout);
    std::fputs("surfreg: interrupted\n", stderr);
    return surfreg::InterruptExitCode(e.signal());
  } catch (const surfreg::InputError& e) {
    std::fprintf(stderr, "surfreg: error: %s\n", surfreg::OneLine(e.what()).c_str());
    return 2;
  } catch (const surfreg::UsageError& e) {
    std::fprintf(stderr, "surfreg: error: %s\nrun 'surfreg help' for usage\n",
                 surfreg::OneLine(e.what()).c_str());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "surfreg: internal error: %s\n", surfreg::OneLine(e.what()).c_str());
    return 1;
  }
}
