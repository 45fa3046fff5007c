#pragma once
// The JSON scene file of the 2D crack solver (format in demos/mpm/README-section.md).
// Reading is strict: an unknown key, a value of the wrong type, a missing required key or
// a value out of range throws shatter::InputError whose message starts with the file name
// and the key path, e.g. "pull.json: bodies[0].shape.radius: expected a number, got a string".
#include <shatter/plugin/mpm/Scene.h>

#include <string>

namespace shatter::mpm {

// Reads and checks a scene file.
Scene loadScene(const std::string& path);

// Parses scene text; `source` names it in messages (a file name, or e.g. "<test>").
Scene parseScene(const std::string& text, const std::string& source);

} // namespace shatter::mpm
