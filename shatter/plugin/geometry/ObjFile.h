#pragma once
// Wavefront OBJ input: what the loader keeps of a file (positions, polygon faces,
// object/group names) and where each face came from, for error messages.
#include <Eigen/Core>
#include <string>
#include <vector>

namespace shatter::geometry {

struct ObjFace {
    std::vector<int> vertices; // 0-based indices into ObjFile::positions
    int line = 0;              // 1-based line in the file
};

// A polyline (`l` statement): the tear lines of a `tear.<body>` object (TearLines.h).
struct ObjPolyline {
    std::vector<int> vertices; // 0-based indices into ObjFile::positions
    int line = 0;              // 1-based line in the file
};

// Faces under one `o` or `g` name. Faces before any name belong to an object named
// after the file stem.
struct ObjObject {
    std::string name;
    int line = 0; // line of the `o`/`g` statement (0 for the implicit first object)
    std::vector<ObjFace> faces;
    std::vector<ObjPolyline> polylines;
};

struct ObjFile {
    std::string path;
    std::vector<Eigen::Vector3d> positions;
    std::vector<int> positionLines; // line of each `v`
    std::vector<ObjObject> objects;
    std::vector<std::string> warnings; // e.g. "mesh.obj: skipped 3 degenerate faces (lines 4, 9, 12)"
};

// Reads an OBJ file: `v`, `f` (any polygon size; `v`, `v/vt`, `v/vt/vn`, `v//vn`,
// negative relative indices), `l` (at least 2 points, `v` or `v/vt`), `o`, `g`; other
// statements are ignored. Throws
// shatter::InputError naming "path:line" for: a missing or unreadable file, a malformed
// number, a non-finite coordinate, an out-of-range or zero index, a face with fewer than
// 3 vertex references (often a file cut short), and a file with no faces. Degenerate faces
// (fewer than 3 distinct vertices, or zero area) are skipped and counted in one warning.
// Bytes quoted from the file are escaped (printable ASCII as is, others as \xNN) and cut
// after 40 bytes (common/QuotedInput.h). Running out of memory is an InputError naming the file.
// Details: a missing file gives "path: cannot open: <reason>", a file without faces
// "path: no faces". A vertex needs x y z (further numbers, w or a colour, are checked and
// dropped). Indices must refer to `v`/`vt`/`vn` lines before the face. Comments, CRLF, a
// byte-order mark and `\` line continuations are handled; an `o`/`g` without a name takes the
// file stem; bytes of a name outside printable ASCII are kept as \xNN text; objects left
// without faces or polylines are dropped. A face's consecutive repeated
// indices are removed; it is degenerate when fewer than 3 remain, an index still repeats
// (a self-touching polygon), or its Newell normal is at most 1e-12 × the squared diagonal
// of the file's bounding box. Unknown statements are listed in one more warning.
ObjFile loadObj(const std::string& path);
// Same from text in memory; `name` stands in for the path in messages.
ObjFile parseObj(const std::string& text, const std::string& name);

} // namespace shatter::geometry
