#pragma once
// The property every loader's fuzz target checks, shared by the libFuzzer targets
// (tests/fuzz/targets, clang only) and the replay of the regression corpus (every build):
// bytes in, a valid result or a shatter::InputError out. Anything else (another exception, a
// non-finite value in an accepted result) is a Bug; crashes, leaks and hangs are the
// sanitizers' and the fuzzer's to catch.
#include <string>

namespace shatter::test {

enum class FuzzOutcome { Accepted, Refused, Bug };

// OBJ text → ObjFile → PhysicalObject: every body has a finite positive mass and finite vertices.
FuzzOutcome checkObjInput(const std::string& bytes);

// TetGen .node and .ele text, separated by the first NUL byte (no NUL: an empty .ele) →
// TetMesh: every tet positive and finite.
FuzzOutcome checkTetGenInput(const std::string& bytes);

// MPM scene JSON → Scene → the up-front limits (fuzzLimits()) → when they hold, a Solver2D
// (seeding, loads, cracks) and one substep.
FuzzOutcome checkSceneInput(const std::string& bytes);

// OBJ text → fracture pattern (one convex cell per object): every cell has a finite positive volume.
FuzzOutcome checkPatternInput(const std::string& bytes);

// What to call the outcome in a message.
const char* outcomeName(FuzzOutcome outcome);

} // namespace shatter::test
