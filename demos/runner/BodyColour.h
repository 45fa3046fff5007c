#pragma once
// The colours every output gives a body (pictures, glTF materials), so a body looks the same
// in a PNG, in Blender and in the browser.
#include <string>

namespace shatter::demo {

struct Rgb {
    double r, g, b; // 0..1, sRGB
};

// A hue from the name (FNV-1a): a body keeps its colour across frames, runs and machines,
// and the fragments of a broken body ("door.7", "door.8") get distinct colours.
Rgb bodyColour(const std::string& name);

// Faces that fracture opened inside the solid (VisualMesh::crackFace): one pale stone colour
// for every body, so fresh breaks read as breaks whatever the body's own colour.
Rgb crackColour();

} // namespace shatter::demo
