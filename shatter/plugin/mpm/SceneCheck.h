#pragma once
// The rules a scene must satisfy whatever it was built from (a file or code): positive cell
// size and moduli, ν < 0.5, valid shapes, cracks inside a body, ... Each violation throws
// shatter::InputError naming the offending key the way the scene file spells it, e.g.
// "pull.json: materials.pmma.nu: must be below 0.5, got 0.5".
#include <shatter/plugin/mpm/Scene.h>

#include <string>

namespace shatter::mpm {

// Physically absurd values are errors too: ν at or above kMaxPlaneStrainNu in plane strain, a
// body faster than kMaxBodySpeed, a material or speed whose CFL step is below kMinTimeStep, and a
// crack segment shorter than kMinCrackSegmentCells x grid.dx.
// What a valid scene costs is checked separately (SceneBudget.h).
void checkScene(const Scene& scene);

constexpr double kMaxPlaneStrainNu = 0.5 - 1e-6;
constexpr double kMaxBodySpeed = 1e4; // m/s
constexpr double kMinTimeStep = 1e-12; // s
constexpr double kMinCrackSegmentCells = 0.05;

// True when p lies in (or on the outline of) any body.
bool insideAnyBody(const Scene& scene, const Vec2& p);

} // namespace shatter::mpm
