// Oriented point clouds on disk: PLY (binary little-endian written; ASCII and both binary
// byte orders read; the vertex element needs x y z nx ny nz) and XYZ text (one point per
// line: x y z nx ny nz; '#' starts a comment). Normals are normalised on reading; a zero
// or non-finite value is refused with the file and the line or point named.
#pragma once

#include <string>

#include "geometry/point_cloud.h"

namespace mpumesh {

PointCloud read_point_cloud(const std::string& path);
void write_point_cloud(const PointCloud& cloud, const std::string& path);

// From memory, for the fuzzers and tests; `ext` is ".ply" or ".xyz".
PointCloud parse_point_cloud(const std::string& bytes, const std::string& ext, const std::string& name);

// Query positions (`mpumesh eval`): text, one point per line, its first three numbers
// x y z (further columns, such as normals, are ignored); '#' starts a comment.
std::vector<Eigen::Vector3d> parse_positions(const std::string& bytes, const std::string& name);
std::vector<Eigen::Vector3d> read_positions(const std::string& path);

}  // namespace mpumesh
