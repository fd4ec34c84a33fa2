#pragma once
// Checks the counts of OFF and OBJ files before assimp reads them. Part of porter::core_io
// (mesh_loader.cpp); not a public header.
//
// assimp's OFF importer allocates (and constructs) the faces and vertices its header asks for
// before reading a line: a 60-byte OFF claiming 1e9 faces took it past 22 GB. Its OBJ importer
// keeps ~200 B per face: a 96 MB file of "f 1 2 3" lines took 2.7 GB, a 256 MiB one would take
// about 7 GB.

#include <string>

namespace porter::detail {

/// "" when the file is neither OFF (by extension or header) nor possibly OBJ (.obj or an
/// extension other than ply, stl, off, dae), or its
/// counts are within kMeshMaxVertices / kMeshMaxFaces (OBJ: face corners within 3 x
/// kMeshMaxFaces, which bounds the triangles) and, for OFF, the file has a line for every
/// vertex and face its header claims; otherwise why not.
std::string check_text_mesh_counts(const std::string& path);

}  // namespace porter::detail
