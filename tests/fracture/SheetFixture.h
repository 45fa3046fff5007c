#pragma once
// A square sheet of n × n quads (spacing h, in the xy plane, facing +z) as OBJ text, with an
// optional tear line along the vertex column `column` from vertex row `from` to row `to`.
// Quad (i, j) covers x in [i h, (i+1) h], y in [j h, (j+1) h]; it is face i + n j.
#include <shatter/plugin/geometry/ObjFile.h>
#include <shatter/plugin/geometry/PhysicalMesh.h>

#include <sstream>
#include <string>

namespace shatter::test {

struct SheetSpec {
    int n = 10;
    double h = 0.1;
    int column = -1; // no tear line
    int from = 0, to = 0;
};

inline std::string sheetObj(const SheetSpec& s) {
    std::ostringstream obj;
    obj << "o sheet\n";
    for (int j = 0; j <= s.n; ++j)
        for (int i = 0; i <= s.n; ++i) obj << "v " << i * s.h << " " << j * s.h << " 0\n";
    auto v = [&](int i, int j) { return 1 + i + (s.n + 1) * j; };
    for (int j = 0; j < s.n; ++j)
        for (int i = 0; i < s.n; ++i)
            obj << "f " << v(i, j) << " " << v(i + 1, j) << " " << v(i + 1, j + 1) << " " << v(i, j + 1) << "\n";
    if (s.column >= 0) {
        obj << "o tear.sheet\nl";
        for (int j = s.from; j <= s.to; ++j) obj << " " << v(s.column, j);
        obj << "\n";
    }
    return obj.str();
}

// The sheet's physical mesh, 1 cm thick.
inline geometry::PhysicalMesh sheetMesh(const SheetSpec& s) {
    geometry::PhysicalMeshSettings settings;
    settings.thickness = 0.01;
    return geometry::buildPhysicalObject(geometry::parseObj(sheetObj(s), "sheet.obj"), settings).bodies.at(0);
}

} // namespace shatter::test
