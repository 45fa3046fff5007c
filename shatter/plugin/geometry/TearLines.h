#pragma once
// Tear lines drawn by the artist (source 000 §3.6: "the artist ... can pre-define tear lines by
// making only a subset of the connections breakable"). In the OBJ file, an object named
// `tear.<body>` holds polylines (`l` statements) whose points are vertices of that body's
// visual mesh; each segment must be an edge of one of the body's faces. The connections
// across those edges are the ones that may break (fracture/BreakableConnections.h).
#include <shatter/plugin/geometry/ObjFile.h>
#include <shatter/plugin/geometry/PhysicalMesh.h>

#include <string>

namespace shatter::geometry {

// Whether an object of that name holds tear lines (it starts with "tear.").
bool isTearName(const std::string& objectName);

// How close (m) a polyline point must be to a visual vertex to be that vertex: 1e-6 of the
// body's bounding-box diagonal, but at least 1e-6 m (coordinates written with six decimals).
double tearPointTolerance(const PhysicalMesh& body);

// Adds the edges along `tear`'s polylines to the tearEdges of the body it names (positions
// in metres, as the bodies). A point matches every visual vertex within tearPointTolerance;
// a segment gives the face edges between the vertices its two ends match. Throws
// shatter::InputError naming "file:line" and the body for: a name with no body after
// "tear.", a body the object does not have, faces in a tear object, a point that is no
// vertex of the body's visual mesh, and a segment that is no edge of its faces.
void addTearLines(const ObjFile& file, const ObjObject& tear, PhysicalObject& object);

} // namespace shatter::geometry
