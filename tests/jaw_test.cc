// Jaw motion over a sequence (faces/jaw.h) against the known motions
// of a synthetic chewing sequence (tests/testing/chewing_sequence.h), the
// boundary split against a brute-force classification, and the jaw config
// (tools/jaw_config.h).
#include "faces/jaw.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>

#include <Eigen/Geometry>

#include "measure/input_error.h"
#include "tests/testing/chewing_sequence.h"
#include "tools/jaw_config.h"
#include "io/plot.h"

namespace surfreg {
namespace {

constexpr double kPi = 3.14159265358979323846;

Eigen::Matrix4d Motion(const Eigen::Vector3d& axis, double angle_deg, const Eigen::Vector3d& shift) {
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m.topLeftCorner<3, 3>() = Eigen::AngleAxisd(angle_deg * kPi / 180, axis.normalized()).toRotationMatrix();
  m.topRightCorner<3, 1>() = shift;
  return m;
}

// The algebra of the header: frame = G(upper ∪ H(lower)) gives U = G⁻¹,
// L = H⁻¹G⁻¹ (the exact registrations), and J = U·L⁻¹ = H.
TEST(JawAlgebra, UpperTimesInverseLowerIsTheJawMotion) {
  std::mt19937_64 rng(7);
  std::normal_distribution<double> normal;
  for (int trial = 0; trial < 20; ++trial) {
    const Eigen::Matrix4d g = Motion({normal(rng), normal(rng), normal(rng)}, 5 * normal(rng),
                                     {normal(rng), normal(rng), normal(rng)});
    const Eigen::Matrix4d h = Motion({normal(rng), normal(rng), normal(rng)}, 10 * normal(rng),
                                     {10 * normal(rng), normal(rng), normal(rng)});
    const Eigen::Matrix4d u = g.inverse();      // upper frame points → reference
    const Eigen::Matrix4d l = (g * h).inverse();  // lower frame points → reference
    const Eigen::Vector4d p(normal(rng), normal(rng), normal(rng), 1.0);
    EXPECT_LT((u * (g * p) - p).norm(), 1e-12);      // U registers the upper part
    EXPECT_LT((l * (g * h * p) - p).norm(), 1e-12);  // L registers the lower part
    const Eigen::Matrix4d j = u * l.inverse();
    EXPECT_LT((j - h).norm(), 1e-12);
  }
}

TEST(JawTrack, RecoversTheChewingMotionOnEveryFrame) {
  ChewingOptions chewing;
  chewing.frames = 8;
  chewing.upper_points = 5000;
  chewing.lower_points = 5000;
  const std::vector<ChewingFrame> frames = MakeChewingSequence(DenseFace(), chewing);
  JawOptions options;
  options.boundary.y_level = chewing.boundary_y;
  options.boundary.margin = 2.0;
  const JawSummary summary = TrackJaw(FrameSurfaces(frames), options);
  ASSERT_EQ(summary.frames.size(), frames.size());
  EXPECT_TRUE(summary.frames[0].is_reference);
  EXPECT_EQ(summary.frames[0].jaw, Eigen::Matrix4d::Identity());
  double max_angle = 0, max_shift = 0;
  for (std::size_t k = 0; k < frames.size(); ++k) {
    const std::array<double, 2> error = MotionDifference(summary.frames[k].jaw, frames[k].jaw);
    max_angle = std::max(max_angle, error[0]);
    max_shift = std::max(max_shift, error[1]);
    EXPECT_LE(error[0], 0.1) << "frame " << k;
    EXPECT_LE(error[1], 0.05) << "frame " << k;
    const std::array<double, 2> head = MotionDifference(summary.frames[k].upper.reference_from_frame,
                                                        frames[k].head.inverse());
    std::printf("frame %zu: opening %.3f deg, jaw error %.4f deg %.4f mm, head error %.4f deg %.4f mm, "
                "iterations %d + %d, %.3f s\n",
                k, frames[k].opening_deg, error[0], error[1], head[0], head[1],
                summary.frames[k].upper.iterations, summary.frames[k].lower.iterations,
                summary.frames[k].seconds);
    if (k > 0) {
      EXPECT_NE(summary.frames[k].upper.verdict, Verdict::kFailed);
      EXPECT_NE(summary.frames[k].lower.verdict, Verdict::kFailed);
    }
  }
  std::printf("max jaw error over %zu frames: %.4f deg, %.4f mm\n", frames.size(), max_angle, max_shift);
  std::printf("%s", summary.BriefReport().c_str());
}

// The two parts of each frame register side by side when threads allow
// (one thread each): every number is the one of the parts in turn on one
// thread, for both costs.
TEST(JawTrack, IsTheSameOnOneAndTwoThreads) {
  ChewingOptions chewing;
  chewing.frames = 4;
  chewing.upper_points = chewing.lower_points = 2000;
  const std::vector<Surface> frames = FrameSurfaces(MakeChewingSequence(DenseFace(), chewing));
  for (const JawCost cost : {JawCost::kAxial, JawCost::kVolume}) {
    std::vector<JawSummary> runs;
    for (const int threads : {1, 2}) {
      JawOptions options;
      options.boundary.y_level = chewing.boundary_y;
      options.cost = cost;
      options.num_threads = threads;
      runs.push_back(TrackJaw(frames, options));
    }
    for (std::size_t k = 0; k < frames.size(); ++k) {
      EXPECT_EQ(runs[1].frames[k].upper.reference_from_frame, runs[0].frames[k].upper.reference_from_frame) << k;
      EXPECT_EQ(runs[1].frames[k].lower.reference_from_frame, runs[0].frames[k].lower.reference_from_frame) << k;
      EXPECT_EQ(runs[1].frames[k].lower.covariance, runs[0].frames[k].lower.covariance) << k;
      EXPECT_EQ(runs[1].frames[k].upper.iterations, runs[0].frames[k].upper.iterations) << k;
    }
  }
}

// The reference frame against a frame that is a rigid copy of it moved by a
// known head motion only (same samples): J = identity, U = G⁻¹.
TEST(JawTrack, HeadMotionAloneGivesIdentityJaw) {
  ChewingOptions chewing;
  chewing.frames = 1;
  const std::vector<ChewingFrame> one = MakeChewingSequence(DenseFace(), chewing);
  const Eigen::Matrix4d g = Motion({0.2, 1.0, 0.3}, 0.8, {0.5, -0.4, 0.3});
  std::vector<std::array<double, 3>> moved = one[0].points;
  for (auto& p : moved) {
    const Eigen::Vector4d q = g * Eigen::Vector4d(p[0], p[1], p[2], 1.0);
    p = {q.x(), q.y(), q.z()};
  }
  JawOptions options;
  options.boundary.y_level = chewing.boundary_y;
  const JawSummary summary =
      TrackJaw({MakeSurface(one[0].points, {}, "a"), MakeSurface(moved, {}, "b")}, options);
  const std::array<double, 2> jaw = MotionDifference(summary.frames[1].jaw, Eigen::Matrix4d::Identity());
  const std::array<double, 2> head = MotionDifference(summary.frames[1].upper.reference_from_frame, g.inverse());
  EXPECT_LT(jaw[0], 1e-3);
  EXPECT_LT(jaw[1], 1e-3);
  EXPECT_LT(head[0], 1e-3);
  EXPECT_LT(head[1], 1e-3);
  EXPECT_EQ(summary.frames[1].upper.verdict, Verdict::kConvergedImproved);
}

// A frame identical to the reference: every kept gap is 0, so is σ. The
// sandwich's central differences have no step (0 Gauss-Newton σ) and JᵀJ
// stands in for the curvature (faces/jaw_internal.h PartSandwichCovariance).
TEST(JawTrack, IdenticalFrameHasZeroSigma) {
  ChewingOptions chewing;
  chewing.frames = 1;
  chewing.upper_points = chewing.lower_points = 2000;
  const std::vector<ChewingFrame> one = MakeChewingSequence(DenseFace(), chewing);
  JawOptions options;
  options.boundary.y_level = chewing.boundary_y;
  const Surface surface = MakeSurface(one[0].points, {}, "a");
  const JawSummary summary = TrackJaw({surface, surface}, options);
  const JawFrame& f = summary.frames[1];
  for (const JawPartResult* part : {&f.upper, &f.lower}) {
    EXPECT_TRUE(part->covariance_ok);
    EXPECT_FALSE(part->covariance_measured_curvature);
    EXPECT_GE(part->covariance_tiles, 32);
    EXPECT_LT(part->covariance.norm(), 1e-20);
  }
  for (int k = 0; k < 6; ++k) EXPECT_LT(f.stddev[k], 1e-9) << k;
}

// A reference in the middle: frames before it are tracked backwards; the
// truth is then relative to that frame: J_k = H_k · H_ref⁻¹ (in the
// reference's skull frame, G_ref⁻¹ conjugated).
TEST(JawTrack, ReferenceInTheMiddle) {
  ChewingOptions chewing;
  chewing.frames = 4;
  chewing.upper_points = chewing.lower_points = 3000;
  chewing.head_angle_deg = 0;
  chewing.head_shift = 0;
  const std::vector<ChewingFrame> frames = MakeChewingSequence(DenseFace(), chewing);
  JawOptions options;
  options.boundary.y_level = chewing.boundary_y;
  options.boundary.margin = 2.0;
  options.reference = 2;
  const JawSummary summary = TrackJaw(FrameSurfaces(frames), options);
  EXPECT_TRUE(summary.frames[2].is_reference);
  for (int k = 0; k < 4; ++k) {
    const Eigen::Matrix4d truth = frames[k].jaw * frames[2].jaw.inverse();
    const std::array<double, 2> error = MotionDifference(summary.frames[k].jaw, truth);
    EXPECT_LE(error[0], 0.1) << "frame " << k;
    EXPECT_LE(error[1], 0.05) << "frame " << k;
  }
}

// A polygon boundary through a whole tracking run: a rectangle whose only
// edge near the face is the line y = boundary_y splits every frame as the y
// level does (inside = lower, the same margin band dropped), so the run must
// give the same motions, and both recover the truth.
TEST(JawTrack, PolygonBoundaryTracksAsTheSameLine) {
  ChewingOptions chewing;
  chewing.frames = 4;
  chewing.upper_points = chewing.lower_points = 3000;
  const std::vector<ChewingFrame> frames = MakeChewingSequence(DenseFace(), chewing);
  const std::vector<Surface> surfaces = FrameSurfaces(frames);
  JawOptions line;
  line.boundary.y_level = chewing.boundary_y;
  line.boundary.margin = 2.0;
  JawOptions polygon = line;
  const double y = chewing.boundary_y;
  polygon.boundary.polygon = {{-1e4, -1e4}, {1e4, -1e4}, {1e4, y}, {-1e4, y}};
  const JawSummary by_line = TrackJaw(surfaces, line);
  const JawSummary by_polygon = TrackJaw(surfaces, polygon);
  ASSERT_EQ(by_polygon.frames.size(), frames.size());
  EXPECT_EQ(by_polygon.reference_upper_points, by_line.reference_upper_points);
  EXPECT_EQ(by_polygon.reference_lower_points, by_line.reference_lower_points);
  for (std::size_t k = 0; k < frames.size(); ++k) {
    EXPECT_LT((by_polygon.frames[k].jaw - by_line.frames[k].jaw).norm(), 1e-9) << "frame " << k;
    const std::array<double, 2> error = MotionDifference(by_polygon.frames[k].jaw, frames[k].jaw);
    EXPECT_LE(error[0], 0.1) << "frame " << k;
    EXPECT_LE(error[1], 0.05) << "frame " << k;
  }
}

// The split against a brute-force classification: point in polygon by the
// winding number (sum of angles) and the distance to the boundary by dense
// sampling of its edges; points within 1e-6 of the margin are skipped.
TEST(JawBoundary, SplitMatchesBruteForce) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> coordinate(-10, 10);
  JawBoundary polygon;
  polygon.polygon = {{-5, -6}, {6, -4}, {3, 0}, {7, 5}, {-4, 6}, {-1, 0}};  // not convex
  polygon.margin = 0.7;
  int counts[3] = {0, 0, 0};
  for (int trial = 0; trial < 2000; ++trial) {
    const double x = coordinate(rng), y = coordinate(rng);
    double winding = 0, distance = 1e300;
    const auto& v = polygon.polygon;
    for (std::size_t i = 0; i < v.size(); ++i) {
      const auto& a = v[i];
      const auto& b = v[(i + 1) % v.size()];
      winding += std::atan2((a[0] - x) * (b[1] - y) - (a[1] - y) * (b[0] - x),
                            (a[0] - x) * (b[0] - x) + (a[1] - y) * (b[1] - y));
      for (int s = 0; s <= 5000; ++s) {  // steps ≤ 0.0025: distance error ≤ 0.00125
        const double t = s / 5000.0;
        distance = std::min(distance, std::hypot(a[0] + t * (b[0] - a[0]) - x, a[1] + t * (b[1] - a[1]) - y));
      }
    }
    if (std::fabs(distance - polygon.margin) < 2e-3) continue;  // sampling resolution
    const JawPart expected = distance < polygon.margin     ? JawPart::kDropped
                             : std::fabs(winding) > kPi ? JawPart::kLower
                                                        : JawPart::kUpper;
    const JawPart got = ClassifyJawPoint(polygon, x, y);
    EXPECT_EQ(got, expected) << x << " " << y;
    ++counts[static_cast<int>(got)];
  }
  EXPECT_GT(counts[0], 100);
  EXPECT_GT(counts[1], 100);
  EXPECT_GT(counts[2], 100);
}

TEST(JawBoundary, EdgeCases) {
  JawBoundary level;
  level.y_level = 2.0;
  EXPECT_EQ(ClassifyJawPoint(level, 0, 2.0), JawPart::kUpper);  // on the level: upper
  EXPECT_EQ(ClassifyJawPoint(level, 0, std::nextafter(2.0, 0.0)), JawPart::kLower);
  level.margin = 0.5;
  EXPECT_EQ(ClassifyJawPoint(level, 0, 2.49), JawPart::kDropped);
  EXPECT_EQ(ClassifyJawPoint(level, 0, 1.51), JawPart::kDropped);
  EXPECT_EQ(ClassifyJawPoint(level, 0, 2.5), JawPart::kUpper);   // at the margin: kept
  EXPECT_EQ(ClassifyJawPoint(level, 0, 1.5), JawPart::kLower);
  JawBoundary square;
  square.polygon = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  EXPECT_EQ(ClassifyJawPoint(square, 0.5, 0.5), JawPart::kLower);
  EXPECT_EQ(ClassifyJawPoint(square, 1.0, 0.5), JawPart::kLower);  // on an edge: inside
  EXPECT_EQ(ClassifyJawPoint(square, 0.0, 0.0), JawPart::kLower);  // on a vertex
  EXPECT_EQ(ClassifyJawPoint(square, 1.5, 0.5), JawPart::kUpper);
  EXPECT_EQ(ClassifyJawPoint(square, 0.5, 1.0 + 1e-12), JawPart::kUpper);
  square.margin = 0.1;
  EXPECT_EQ(ClassifyJawPoint(square, 1.0, 0.5), JawPart::kDropped);
  EXPECT_EQ(ClassifyJawPoint(square, 1.05, 0.5), JawPart::kDropped);
  EXPECT_EQ(ClassifyJawPoint(square, 0.5, 0.5), JawPart::kLower);
}

// The reference's split as TrackJaw reports it equals a direct count.
TEST(JawTrack, ReferenceSplitCounts) {
  ChewingOptions chewing;
  chewing.frames = 2;
  chewing.upper_points = chewing.lower_points = 2000;
  const std::vector<ChewingFrame> frames = MakeChewingSequence(DenseFace(), chewing);
  JawOptions options;
  options.boundary.y_level = -30;
  options.boundary.margin = 3;
  const JawSummary summary = TrackJaw(FrameSurfaces(frames), options);
  int upper = 0, lower = 0, dropped = 0;
  for (const auto& p : frames[0].points) {
    if (std::fabs(p[1] + 30) < 3) {
      ++dropped;
    } else {
      ++(p[1] >= -30 ? upper : lower);
    }
  }
  EXPECT_EQ(summary.reference_upper_points, upper);
  EXPECT_EQ(summary.reference_lower_points, lower);
  EXPECT_EQ(summary.frames[0].dropped, dropped);
}

TEST(JawTrack, InvalidInputs) {
  ChewingOptions chewing;
  chewing.frames = 2;
  chewing.upper_points = chewing.lower_points = 500;
  const std::vector<Surface> frames = FrameSurfaces(MakeChewingSequence(DenseFace(), chewing));
  JawOptions options;
  options.boundary.y_level = 500;  // everything is lower
  EXPECT_THROW(TrackJaw(frames, options), InputError);
  options.boundary.y_level = -35;
  options.reference = 2;
  EXPECT_THROW(TrackJaw(frames, options), InputError);
  options.reference = 0;
  options.trim_fraction = 0.5;
  EXPECT_THROW(TrackJaw(frames, options), InputError);
  options.trim_fraction = 0.1;
  options.boundary.polygon = {{0, 0}, {1, 1}};
  EXPECT_THROW(TrackJaw(frames, options), InputError);
  EXPECT_THROW(TrackJaw(std::vector<Surface>(), JawOptions()), InputError);
}

// --- the config (tools/jaw_config.h) ---

class JawConfigTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::path(::testing::TempDir()) /
           ("jaw_config_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_ / "frames");
    for (const char* name : {"b.xyz", "a.xyz", "c.ply.txt"}) {
      std::ofstream(dir_ / "frames" / name) << "0 0 0\n1 0 0\n0 1 0\n";
    }
    std::ofstream(dir_ / "frames" / "notes.md") << "not a frame\n";
  }
  std::string Path(const std::string& name) const { return (dir_ / name).string(); }
  // The InputError message of finishing a config made of `yaml`.
  std::string Error(const std::string& yaml) const {
    try {
      JawConfig config;
      ApplyJawYaml(yaml, "jaw.yaml", &config);
      FinishJawConfig(&config);
    } catch (const InputError& e) {
      return e.what();
    }
    return "";
  }
  std::filesystem::path dir_;
};

TEST_F(JawConfigTest, FolderSortedByNameAndDefaults) {
  JawConfig config;
  ApplyJawYaml("frames: " + Path("frames") + "\nboundary_y: -35\n", "jaw.yaml", &config);
  FinishJawConfig(&config);
  ASSERT_EQ(config.frame_files.size(), 3u);  // notes.md is not a surface file
  EXPECT_EQ(std::filesystem::path(config.frame_files[0]).filename(), "a.xyz");
  EXPECT_EQ(std::filesystem::path(config.frame_files[1]).filename(), "b.xyz");
  const JawOptions defaults;
  EXPECT_EQ(config.reference_index, 0);
  EXPECT_EQ(config.options.cost, defaults.cost);
  EXPECT_EQ(config.options.trim_fraction, defaults.trim_fraction);
  EXPECT_EQ(config.options.max_iterations, defaults.max_iterations);
  EXPECT_EQ(config.options.boundary.margin, defaults.boundary.margin);
  EXPECT_EQ(JawConfigValue(config, "orientation"), "as_is");
  EXPECT_EQ(config.options.boundary.y_level, -35);
}

TEST_F(JawConfigTest, FlagsOverrideAndReferenceByFile) {
  JawConfig config;
  ApplyJawYaml("frames: [" + Path("frames/b.xyz") + ", " + Path("frames/a.xyz") +
                   "]\nboundary_y: 1\ncost: axial\nreference: " + Path("frames/a.xyz") + "\n",
               "jaw.yaml", &config);
  ApplyJawFlag("cost", "volume", &config);
  ApplyJawFlag("boundary_margin", "2.5", &config);
  ApplyJawFlag("orientation", "10,0,0", &config);
  FinishJawConfig(&config);
  EXPECT_EQ(config.options.cost, JawCost::kVolume);
  EXPECT_EQ(config.options.boundary.margin, 2.5);
  EXPECT_EQ(config.reference_index, 1);
  EXPECT_EQ(config.orientation.orientation, FaceOrientation::kGiven);
  EXPECT_EQ(config.Where("cost"), "flag '--cost'");
}

// Neither boundary: find_boundary; a boundary_y cleared by an empty flag
// likewise; the path keys.
TEST_F(JawConfigTest, FindsTheBoundaryWhenNoneIsGivenAndPathKeys) {
  JawConfig config;
  ApplyJawYaml("frames: " + Path("frames") + "\npath_point: [1.5, -80, -70]\n", "jaw.yaml", &config);
  FinishJawConfig(&config);
  EXPECT_TRUE(config.options.find_boundary);
  EXPECT_FALSE(config.has_boundary_y);
  EXPECT_EQ(JawConfigValue(config, "boundary_y"), "");
  ASSERT_TRUE(config.options.path_point.has_value());
  EXPECT_EQ(*config.options.path_point, Eigen::Vector3d(1.5, -80, -70));
  EXPECT_EQ(JawConfigValue(config, "path_point"), "[1.5, -80, -70]");
  JawConfig given;
  ApplyJawYaml("frames: " + Path("frames") + "\nboundary_y: -35\n", "jaw.yaml", &given);
  FinishJawConfig(&given);
  EXPECT_FALSE(given.options.find_boundary);
  EXPECT_FALSE(given.options.path_point.has_value());
  EXPECT_EQ(JawConfigValue(given, "path_point"), "");
  ApplyJawFlag("boundary_y", "", &given);
  ApplyJawFlag("path_point", "0,1,2", &given);
  FinishJawConfig(&given);
  EXPECT_TRUE(given.options.find_boundary);
  EXPECT_EQ(*given.options.path_point, Eigen::Vector3d(0, 1, 2));
}

TEST_F(JawConfigTest, ErrorsNameTheKeyOrFile) {
  const std::string frames = "frames: " + Path("frames") + "\n";
  EXPECT_NE(Error(frames + "boundry_y: 1\n").find("did you mean 'boundary_y'"), std::string::npos)
      << Error(frames + "boundry_y: 1\n");
  EXPECT_NE(Error(frames + "boundary_y: 1\nmax_iterations: many\n").find("jaw.yaml:3: key 'max_iterations'"),
            std::string::npos);
  EXPECT_NE(Error(frames + "boundary_y: [1, 2]\n").find("key 'boundary_y'"), std::string::npos);
  EXPECT_NE(Error(frames + "boundary_y: 1\ncost: fast\n").find("expects one of axial, volume"), std::string::npos);
  const std::string missing = Error("frames: [" + Path("frames/a.xyz") + ", " + Path("nope.xyz") + "]\nboundary_y: 1\n");
  EXPECT_NE(missing.find("key 'frames'"), std::string::npos) << missing;
  EXPECT_NE(missing.find("nope.xyz"), std::string::npos) << missing;
  std::filesystem::create_directories(dir_ / "empty");
  const std::string empty = Error("frames: " + Path("empty") + "\nboundary_y: 1\n");
  EXPECT_NE(empty.find("has no surface files"), std::string::npos) << empty;
  EXPECT_EQ(Error(frames), "");  // no boundary: found from the frames (FindsTheBoundaryWhenNoneIsGiven)
  EXPECT_NE(Error(frames + "boundary_y: 1\nreference: 7\n").find("key 'reference'"), std::string::npos);
  EXPECT_NE(Error(frames + "boundary_y: 1\nplot: " + Path("p.jpg") + "\n").find("key 'plot'"), std::string::npos);
  EXPECT_NE(Error(frames + "boundary_y: 1\noutput_csv: " + Path("no/dir/x.csv") + "\n").find("key 'output_csv'"),
            std::string::npos);
  EXPECT_NE(Error(frames + "boundary_y: 1\nboundary_polygon: " + Path("none.txt") + "\n").find("not both"),
            std::string::npos);
  EXPECT_NE(Error(frames + "boundary_polygon: " + Path("none.txt") + "\n").find("key 'boundary_polygon'"),
            std::string::npos);
  EXPECT_NE(Error(frames + "boundary_y: 1\nboundary_y: 2\n").find("given twice"), std::string::npos);
  EXPECT_NE(Error(frames + "boundary_y: 1\norientation: sideways\n").find("key 'orientation'"), std::string::npos);
  EXPECT_NE(Error(frames + "boundary_y: 1\npath_point: [1, 2]\n").find("key 'path_point'"), std::string::npos);
  EXPECT_NE(Error(frames + "boundary_y: 1\npath_plot: " + Path("p.svg") + "\n").find("key 'path_plot'"),
            std::string::npos);
  // (A build without Cairo refuses a .png first, saying so.)
  EXPECT_NE(Error(frames + "boundary_y: 1\nplot: " + Path("p.png") + "\npath_plot: " + Path("p.png") + "\n")
                .find(PngFiguresBuilt() ? "is also plot" : "Cairo"),
            std::string::npos);
  JawConfig config;
  EXPECT_THROW(ApplyJawFlag("boundary", "1", &config), InputError);
}

TEST(JawConfigShipped, ParsesAndMatchesTheShippedTruth) {
  // The shipped config draws a plot: refused up front by a build without Cairo.
  if (!PngFiguresBuilt()) GTEST_SKIP() << "built without Cairo (SURFREG_PLOTS OFF)";
  // The config's paths are relative to the project root, and its outputs go
  // to out/: run in a scratch directory holding a link to configs/ and an
  // empty out/, so that the test neither needs nor touches the tree's out/.
  const std::string face = DenseFacePath();
  const std::filesystem::path root =
      face.substr(0, face.size() - std::string("/configs/data/mannequin_face_dense.xyz").size());
  const std::filesystem::path scratch =
      std::filesystem::path(::testing::TempDir()) / "surfreg_jaw_config_shipped";
  std::filesystem::remove_all(scratch);
  std::filesystem::create_directories(scratch / "out");
  std::filesystem::create_directory_symlink(root / "configs", scratch / "configs");
  std::filesystem::current_path(scratch);
  JawConfig config;
  ApplyJawConfigFile("configs/jaw_chewing.yaml", &config);
  FinishJawConfig(&config);
  EXPECT_EQ(config.frame_files.size(), 10u);
  EXPECT_EQ(config.reference_index, 0);
  EXPECT_TRUE(config.has_boundary_y);
  std::filesystem::current_path(root);
  std::filesystem::remove_all(scratch);
}

// Not a test: SURFREG_WRITE_CHEWING=DIR writes the shipped example sequence
// (configs/data/chewing/: 10 frames of 3000 + 3000 points, one chewing cycle)
// and its truth files into DIR.
TEST(JawShippedData, WriteWhenAsked) {
  const char* directory = std::getenv("SURFREG_WRITE_CHEWING");
  if (directory == nullptr) GTEST_SKIP() << "set SURFREG_WRITE_CHEWING=DIR to write the example";
  ChewingOptions chewing;
  chewing.frames = 10;
  chewing.period_frames = 10;
  chewing.upper_points = 3000;
  chewing.lower_points = 3000;
  ASSERT_TRUE(WriteChewingSequence(MakeChewingSequence(DenseFace(), chewing), directory));
}

}  // namespace
}  // namespace surfreg
