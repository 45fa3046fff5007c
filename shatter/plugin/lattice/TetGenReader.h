#pragma once
// TetGen's .node/.ele files (the format TetGen, NETGEN exporters and most mesh tools write).
#include <shatter/plugin/lattice/TetMesh.h>

#include <string>

namespace shatter::lattice {

// Reads PATH.node and PATH.ele; `path` may name either file or their common stem.
// Indices may start at 0 or 1 (taken from the first node, as TetGen does); attributes,
// boundary markers, region attributes and the six extra nodes of second-order (-o2)
// elements are read past. Every error is a shatter::InputError that names the file and line
// and, for elements, the element number as written in the file: an unreadable or missing
// file, a malformed header or line, a non-finite coordinate, a node index out of range, a
// degenerate or inverted tet; then validateTetMesh's checks (non-manifold, disconnected).
// A file whose tets are all inverted (the opposite corner-order convention) is read with
// every tet reordered and a warning in TetMesh::warnings; a mix of orientations is an error.
// A count in a header is trusted only as far as the bytes that follow it can hold (a point
// line takes at least 8 bytes, an element line 10, or 22 with 10 nodes): a header declaring
// 10^12 entries allocates no more than the file's size allows and is an error naming the line
// where the file ends; counts above 2^31 - 1 are errors at the header.
TetMesh readTetGen(const std::string& path);

// The same from the two files' text in memory; `stem` names them in messages (STEM.node, STEM.ele).
TetMesh parseTetGen(const std::string& nodeText, const std::string& eleText, const std::string& stem);

// Writes mesh as PATH.node and PATH.ele (zero-based, no attributes). Throws
// shatter::InputError when a file cannot be written.
void writeTetGen(const TetMesh& mesh, const std::string& stem);

} // namespace shatter::lattice
