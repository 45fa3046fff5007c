#pragma once
// The rules a scene must satisfy whatever it was built from (a file or code): positive cell
// size and moduli, ν < 0.5, valid shapes, cracks inside a body, ... Each violation throws
// shatter::InputError naming the offending key the way the scene file spells it, e.g.
// "pull.json: materials.pmma.nu: must be below 0.5, got 0.5".
#include <shatter/plugin/mpm/Scene.h>

#include <string>

namespace shatter::mpm {

void checkScene(const Scene& scene);

// True when p lies in (or on the outline of) any body.
bool insideAnyBody(const Scene& scene, const Vec2& p);

} // namespace shatter::mpm
