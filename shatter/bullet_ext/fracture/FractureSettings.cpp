#include <shatter/bullet_ext/fracture/FractureSettings.h>

#include <shatter/plugin/common/SettingCheck.h>

#include <algorithm>
#include <cstdint>
#include <cmath>

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

FractureMode fractureModeNamed(const std::string& name) {
    if (name == "shatter") return FractureMode::Shatter;
    if (name == "subdivide") return FractureMode::Subdivide;
    throw InputError("unknown fracture mode '" + name + "' (shatter, subdivide)");
}

const char* toString(FractureMode mode) {
    switch (mode) {
    case FractureMode::Shatter: return "shatter";
    case FractureMode::Subdivide: return "subdivide";
    }
    return "unknown";
}

void FractureSettings::setCells(int cells) {
    voronoi.cells = cells;
    glass.rings = std::max(1, int(std::lround(std::sqrt(cells / 3.0))));
    glass.sectors = std::max(3, int(std::lround(double(cells) / glass.rings)));
    grid.count = std::max(1, int(std::lround(std::cbrt(double(cells)))));
}

namespace {

// A generated pattern with the body's radius, its settings checked first.
template <class PatternSettings, class Generate>
fracture::FracturePattern generated(PatternSettings settings, double radius, const std::string& body,
                                    std::uint64_t seed, Generate generate) {
    settings.radius = radius;
    settings.check(body);
    return generate(settings, seed);
}

} // namespace

fracture::FracturePattern FractureSettings::makePattern(const std::string& body) const {
    fracture::FracturePattern out;
    switch (pattern) {
    case PatternKind::Voronoi: out = generated(voronoi, radius, body, seed, fracture::voronoiPattern); break;
    case PatternKind::Glass: out = generated(glass, radius, body, seed, fracture::glassPattern); break;
    case PatternKind::Grid: out = generated(grid, radius, body, seed, fracture::gridPattern); break;
    case PatternKind::File:
        out = fracture::loadPattern(patternFile);
        out.radius = radius;
        break;
    }
    fracture::checkPattern(out, "body '" + body + "': fracture pattern");
    return out;
}

void FractureSettings::check(const std::string& body) const {
    if (!enabled) return;
    requireSetting(mode == FractureMode::Shatter || mode == FractureMode::Subdivide, body, "fracture mode",
                   "Shatter or Subdivide", int(mode));
    requirePositive(body, "fracture threshold", threshold);
    requirePositive(body, "fracture radius", radius);
    requirePositive(body, "fracture minimum piece size", minimumPieceSize);
    requireNonNegative(body, "fracture hull size", hullBelow);
    requireAtLeast(body, "fracture depth", depth, 0);
    requireNonNegative(body, "fracture cool-down", coolDown);
    requireAtLeast(body, "fracture contact delay (steps)", contactDelaySteps, 0);
    requireAtLeast(body, "fracture event spacing (steps)", eventSpacingSteps, 0);
    switch (pattern) {
    case PatternKind::Voronoi: voronoi.check(body); break;
    case PatternKind::Glass: glass.check(body); break;
    case PatternKind::Grid: grid.check(body); break;
    case PatternKind::File:
        if (patternFile.empty())
            throw InputError("body '" + body + "': fracture pattern file is empty (PatternKind::File needs an OBJ of cells)");
        break;
    }
}

} // namespace shatter
