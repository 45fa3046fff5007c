#pragma once
// One object of a frame as the output writers see it: a name and a world-space polygon mesh.
#include <shatter/plugin/geometry/VisualMesh.h>

#include <Eigen/Geometry>

#include <string>

namespace shatter::demo {

struct NamedMesh {
    std::string name;
    geometry::VisualMesh mesh; // world coordinates, polygons counter-clockwise from outside
    // Polygon edges are worth drawing on faceted shapes (fracture pieces, boxes) but turn a
    // finely tessellated sphere or capsule into a dark blur.
    bool outlined = true;
    // The ground: written to the OBJ as a quad, drawn by the renderer as a checkered floor.
    bool ground = false;
    // Where the body's own coordinates are in the world (mesh = pose × its shape): lets the
    // writers tell rigid motion (pose only) from a change of shape (dents, tears, soft bodies).
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
};

} // namespace shatter::demo
