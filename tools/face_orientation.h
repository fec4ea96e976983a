#pragma once
// The text form of a face's orientation (faces/face_frame.h), as the
// face commands' flags and the jaw config take it.
#include <string>

#include "faces/face_frame.h"

namespace surfreg {

// Parses the text form of a face orientation into options->orientation (and
// options->rotation_deg): "auto" (principal axes and the nose heuristics),
// "as_is" (already in the frame's orientation) or a rotation vector
// "RX,RY,RZ" in degrees (also "[RX, RY, RZ]"), axis × angle, taking input
// coordinates to the frame. Other fields of *options are left as they are.
// Throws InputError "<where>: ..." (`where` e.g. "--orientation" or
// "face.yaml:4: key 'orientation'") for anything else.
void FaceOrientationFromString(const std::string& text, const std::string& where,
                               FaceFrameOptions* options);

// The text form of options.orientation: "auto", "as_is" or "RX,RY,RZ"
// (17 significant digits), which FaceOrientationFromString reads back.
std::string FaceOrientationToString(const FaceFrameOptions& options);

}  // namespace surfreg
