#pragma once
// A triangle mesh as files hold it (io/mesh_reader.h): what face scans
// come as before they become height fields (faces/face_frame.h).
#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace surfreg {

// Vertices and triangles (indices into `vertices`, counter-clockwise or not).
// A point cloud is a mesh without triangles.
struct Mesh {
  std::vector<std::array<double, 3>> vertices;
  std::vector<std::array<int32_t, 3>> triangles;
  std::string source;  // where it came from (for messages)
};

}  // namespace surfreg
