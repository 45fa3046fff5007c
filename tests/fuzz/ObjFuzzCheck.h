#pragma once
// The property both OBJ fuzzers check: bytes in, a valid physical object or an InputError out.
#include <shatter/plugin/geometry/ObjFile.h>
#include <shatter/plugin/geometry/PhysicalMesh.h>

#include <cmath>
#include <cstdio>
#include <string>

namespace shatter::test {

enum class ObjOutcome { Accepted, Refused, Bug };

inline ObjOutcome checkObjInput(const std::string& text) {
    try {
        const auto object = geometry::buildPhysicalObject(geometry::parseObj(text, "fuzz.obj"));
        for (const auto& body : object.bodies) {
            if (!(body.mass.mass > 0.0) || !std::isfinite(body.mass.mass)) return ObjOutcome::Bug;
            for (const auto& p : body.primitives)
                for (const auto& v : p.vertices())
                    if (!v.allFinite()) return ObjOutcome::Bug;
        }
        return ObjOutcome::Accepted;
    } catch (const InputError&) {
        return ObjOutcome::Refused;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "unexpected exception: %s\n", e.what());
        return ObjOutcome::Bug;
    }
}

} // namespace shatter::test
