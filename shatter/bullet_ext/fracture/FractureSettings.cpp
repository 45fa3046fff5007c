#include <shatter/bullet_ext/fracture/FractureSettings.h>

#include <shatter/plugin/common/SettingCheck.h>

namespace shatter {

PatternKind patternKindNamed(const std::string& name) {
    if (name == "voronoi") return PatternKind::Voronoi;
    if (name == "glass") return PatternKind::Glass;
    if (name == "grid") return PatternKind::Grid;
    throw InputError("unknown fracture pattern '" + name + "' (voronoi, glass, grid, or an OBJ file of cells)");
}

const char* toString(PatternKind kind) {
    switch (kind) {
    case PatternKind::Voronoi: return "voronoi";
    case PatternKind::Glass: return "glass";
    case PatternKind::Grid: return "grid";
    case PatternKind::File: return "file";
    }
    return "unknown";
}

void FractureSettings::check(const std::string& body) const {
    if (!enabled) return;
    requireAtLeast(body, "fracture cells", cells, 1);
    requirePositive(body, "fracture threshold", threshold);
    requirePositive(body, "fracture radius", radius);
    requirePositive(body, "fracture minimum piece size", minimumPieceSize);
    requireAtLeast(body, "fracture depth", depth, 0);
    requireNonNegative(body, "fracture cool-down", coolDown);
    if (pattern == PatternKind::File && patternFile.empty())
        throw InputError("body '" + body + "': fracture pattern file is empty (PatternKind::File needs an OBJ of cells)");
}

} // namespace shatter
