#include "tests/fuzz/FuzzChecks.h"

#include <shatter/plugin/common/InputError.h>
#include <shatter/plugin/fracture/FracturePattern.h>
#include <shatter/plugin/geometry/ObjFile.h>
#include <shatter/plugin/geometry/PhysicalMesh.h>
#include <shatter/plugin/lattice/TetGenReader.h>

#include <cmath>
#include <cstdio>
#include <exception>

namespace shatter::test {

namespace {

// Runs `check` and maps an InputError to Refused and every other exception to Bug.
template <class Check>
FuzzOutcome guarded(const Check& check) {
    try {
        return check() ? FuzzOutcome::Accepted : FuzzOutcome::Bug;
    } catch (const InputError&) {
        return FuzzOutcome::Refused;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "unexpected exception: %s\n", e.what());
        return FuzzOutcome::Bug;
    }
}

} // namespace

FuzzOutcome checkObjInput(const std::string& bytes) {
    return guarded([&] {
        const auto object = geometry::buildPhysicalObject(geometry::parseObj(bytes, "fuzz.obj"));
        for (const auto& body : object.bodies) {
            if (!(body.mass.mass > 0.0) || !std::isfinite(body.mass.mass)) return false;
            for (const auto& p : body.primitives)
                for (const auto& v : p.vertices())
                    if (!v.allFinite()) return false;
        }
        return true;
    });
}

FuzzOutcome checkTetGenInput(const std::string& bytes) {
    return guarded([&] {
        const size_t split = bytes.find('\0');
        const std::string node = bytes.substr(0, split);
        const std::string ele = split == std::string::npos ? std::string() : bytes.substr(split + 1);
        const lattice::TetMesh mesh = lattice::parseTetGen(node, ele, "fuzz");
        for (const lattice::Tet& t : mesh.tets) {
            const double v = lattice::signedVolume(mesh, t);
            if (!(v > 0.0) || !std::isfinite(v)) return false;
        }
        return true;
    });
}

FuzzOutcome checkPatternInput(const std::string& bytes) {
    return guarded([&] {
        const fracture::FracturePattern pattern = fracture::patternFromObj(geometry::parseObj(bytes, "fuzz.obj"));
        for (const auto& cell : pattern.cells)
            if (!(cell.volume() > 0.0) || !std::isfinite(cell.volume())) return false;
        return std::isfinite(pattern.radius);
    });
}

const char* outcomeName(FuzzOutcome outcome) {
    switch (outcome) {
    case FuzzOutcome::Accepted: return "accepted";
    case FuzzOutcome::Refused: return "refused with an InputError";
    case FuzzOutcome::Bug: return "a bug";
    }
    return "?";
}

} // namespace shatter::test
