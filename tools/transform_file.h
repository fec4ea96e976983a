#pragma once
// Rigid transforms in files: what `surfreg transform --transform` and the
// align key `initial_transform` read, and the text `matrix_txt` writes.
//
// Two formats, told apart by the first character that is not blank or in a
// '#' comment:
//   '{'   surfreg's align JSON (`align --output=x.json`): its "matrix"
//         member, 4 rows of 4 numbers (or 16 numbers), row-major;
//   else  text: 16 numbers, row-major, separated by blanks and/or commas,
//         normally 4 lines of 4; '#' starts a comment (whole line or
//         trailing). What CloudCompare's -APPLY_TRANS and pc_align's
//         --initial-transform read and write, and what MatrixText writes.
// Either way the matrix maps moving → reference: p' = M · [p; 1].
//
// Checks: exactly 16 numbers, all finite; the last row 0 0 0 1; the 3 × 3
// part a rotation: every entry of RᵀR − I within kRotationTolerance, and
// det R > 0. A file written with 7 or more significant digits passes.
// Errors throw InputError "LABEL: FILE[:LINE]: reason" (one line), LABEL
// saying where the file was named ("flag '--transform'").
#include <Eigen/Core>
#include <array>
#include <string>

namespace surfreg {

inline constexpr double kRotationTolerance = 1e-6;

Eigen::Matrix4d ReadTransformFile(const std::string& path, const std::string& label);

// The same checks on a matrix from elsewhere; "" if it is a rigid motion,
// else the reason ("not a rigid motion: ...").
std::string RigidMotionProblem(const Eigen::Matrix4d& m);

// Four lines of four numbers, %.17g (reads back as the same doubles).
std::string MatrixText(const Eigen::Matrix4d& m);

// The 16 numbers row-major on one line, separated by single blanks: the
// `matrix` option of PDAL's filters.transformation.
std::string MatrixOneLine(const Eigen::Matrix4d& m);

// The 16 numbers row-major (what io/las_writer.h takes).
std::array<double, 16> RowMajor(const Eigen::Matrix4d& m);

}  // namespace surfreg
