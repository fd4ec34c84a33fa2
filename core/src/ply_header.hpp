#pragma once
// Checks a PLY file's header and lists before assimp reads it: assimp allocates what the
// header's element counts ask for (a 14-line file claiming 1e9 vertices drove it past 8 GB) and
// what each list's count asks for (one face line claiming 399125025 indices: 3.2 GB). Part of
// porter::core_io (mesh_loader.cpp); not a public header.

#include <string>

namespace porter::detail {

/// "" when the file is not PLY or its header is consistent with its size; otherwise why not
/// (an unterminated header, an unknown format or type, counts the bytes after the header cannot
/// hold, counts above kMeshMaxVertices / kMeshMaxFaces, or a list claiming more values than its
/// line has characters (ASCII) or more bytes than the file has left (binary)).
std::string check_ply_header(const std::string& path);

}  // namespace porter::detail
