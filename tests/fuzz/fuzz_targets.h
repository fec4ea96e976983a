#pragma once
// The fuzz targets (issue 7): one per file parser, and the measure on small
// random clouds. Each takes arbitrary bytes and returns normally when the
// input is accepted or rejected with InputError (the only error a user may
// see for bad input). Anything else is a finding: another exception type, a
// broken invariant (thrown as std::logic_error "fuzz invariant: ..."), or
// what the sanitizers catch (crash, leak, undefined behaviour, a hang that
// libFuzzer's -timeout turns into a failure).
//
// The same functions run in two places: the libFuzzer programs of
// tests/fuzz/ (clang, SURFREG_FUZZ=ON), and fuzz_corpus_test (any compiler),
// which runs every file of tests/fuzz/corpus/<target>/ through its target so
// that the seeds and every input a fuzzer once found stay regression tests.
#include <string>
#include <string_view>
#include <vector>

namespace surfreg::fuzz {

using FuzzFunction = void (*)(std::string_view data);

struct FuzzTarget {
  const char* name;  // also the corpus folder: tests/fuzz/corpus/<name>/
  FuzzFunction run;
};

// Surface readers on the bytes as a whole file (ReadXyz, ReadPly, ReadOff, ReadObj).
void FuzzXyz(std::string_view data);
void FuzzPly(std::string_view data);
void FuzzOff(std::string_view data);
void FuzzObj(std::string_view data);
// The LAS reader (ReadLas): all points with their CRS, then class 2 only;
// and the LAS writer's MovedLas of the same bytes.
void FuzzLas(std::string_view data);
// The mask polygon reader (io/polygon_reader.h).
void FuzzPolygon(std::string_view data);
// The align YAML config: ApplyAlignYaml, then the option checks
// (AlignOptions::IsValid) on what it produced.
void FuzzAlignConfig(std::string_view data);
// Measure() on two small clouds decoded from the bytes (see fuzz_targets.cc):
// ρd, ρ'd, the areas and volumes are finite and >= 0, fill + cut = ρd,
// ρd <= overlap × (height range), and ρd(A, B) = ρd(B, A) to a relative
// tolerance.
void FuzzMeasure(std::string_view data);
// A mesh with triangles (io/mesh_reader.h): the first byte picks the
// format (0: .off, 1: .ply, 2: .obj, modulo 3), the rest is the file; a mesh
// read is then normalized (faces/face_frame.h).
void FuzzMesh(std::string_view data);
void FuzzJawConfig(std::string_view data);    // tools/jaw_config.h, YAML text
void FuzzSweepConfig(std::string_view data);  // tools/sweep_config.h, YAML text

// All of the above, in a fixed order.
const std::vector<FuzzTarget>& FuzzTargets();

}  // namespace surfreg::fuzz
