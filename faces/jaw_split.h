#pragma once
// The boundary between the upper (skull) and lower (jaw) parts found from
// the sequence itself, when neither a level nor a polygon is given
// (JawOptions::find_boundary; docs/faces.md, Jaw motion). The two parts are
// the two rigid parts of the sequence; the boundary is the y level (in the
// reference frame, y running chin → forehead) that best separates them:
// 1. skull: the points in the upper half of the reference's y range (the
//    mouth lies in the lower half of a face's height). Each frame's points
//    there (split where the previous frame's skull motion puts them, as the
//    tracking does) are registered onto the reference's: U_k;
// 2. each reference point's gap to frame k moved by U_k (the axial gap,
//    cos(slope)-weighted as the tracking's): small where the face moved
//    with the skull, large where it moved with the jaw. The frame whose
//    lower half has the largest median |gap| is the most open; its gaps
//    decide;
// 3. labels: moving where |gap| > threshold = max(kSplitNoiseMultiple × the
//    skull's robust σ (1.4826 × median |gap| of the upper half), 1e-9 × the
//    face's height);
// 4. the level: the one with the fewest labels on the wrong side (moving
//    above, still below); of several, the median one.
// The margin is the given boundary.margin. Refused (InputError, one line
// saying to give boundary_y) when the reference points below the level do
// not move (their median |gap| ≤ the threshold: no frame opens the jaw
// beyond the noise) or either side has fewer than min_part_points points.
//
// Each side is subsampled to at most kSplitMaxPoints points by a fixed
// stride: the level needs hundreds of points, not every sample.
#include <functional>

#include "faces/jaw.h"

namespace surfreg {

inline constexpr double kSplitNoiseMultiple = 4.0;
inline constexpr int kSplitMaxPoints = 8000;

// `load(k)` as for TrackJaw: called once per frame, from the reference
// outwards. `search`, if given, gets how the level was found.
JawBoundary FindJawBoundary(int count, const std::function<Surface(int)>& load,
                            const JawOptions& options, JawBoundarySearch* search = nullptr);

}  // namespace surfreg
