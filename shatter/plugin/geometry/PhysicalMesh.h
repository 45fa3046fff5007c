#pragma once
// The physical mesh of one body (source 000 §3.1): convex polyhedron primitives derived
// from the visual mesh, the graph of which primitives touch at rest, the visual mesh they
// carry, and the body's mass properties.
#include <shatter/plugin/geometry/ConvexPolyhedron.h>
#include <shatter/plugin/geometry/MassProperties.h>
#include <shatter/plugin/geometry/ObjFile.h>
#include <shatter/plugin/geometry/VisualMesh.h>

#include <Eigen/Geometry>
#include <string>
#include <utility>
#include <vector>

namespace shatter::geometry {

// The length unit of a mesh's coordinates.
enum class LengthUnit { Metres, Centimetres, Millimetres };
double metresPer(LengthUnit unit);
// "m", "cm" or "mm"; throws shatter::InputError listing them for anything else.
LengthUnit lengthUnitNamed(const std::string& name);

struct PhysicalMeshSettings {
    // What one unit of the input coordinates is, and a further factor: the coordinates are
    // multiplied by metresPer(units) × scale when the physical mesh is built (meshes authored
    // in millimetres or centimetres, or at the wrong size). Everything below, and every
    // length of the built mesh, is in metres.
    LengthUnit units = LengthUnit::Metres;
    double scale = 1.0;
    // Extrusion depth of open surfaces along the negative face normal, in metres.
    // 0 picks the default: 1% of the diagonal of the body's bounding box.
    double thickness = 0.0;
    // kg/m³ (default: water-like 1000).
    double density = 1000.0;
    // Two primitives are connected when their distance is at most this, in metres.
    // 0 picks the default: 1e-4 × the diagonal of the body's bounding box.
    double contactTolerance = 0.0;

    // Scale and density positive, thickness and contact tolerance positive or 0 (the
    // default); all finite.
    void check(const std::string& body) const;
    double metresPerInputUnit() const { return metresPer(units) * scale; }
};

struct PhysicalMesh {
    std::string name;
    std::vector<ConvexPolyhedron> primitives; // in mesh coordinates
    std::vector<int> sourceFace;              // per primitive: visual face it came from (-1 for a closed convex part)
    std::vector<std::pair<int, int>> connections; // primitive pairs (a < b) that touch or overlap at rest
    VisualMesh visual;                            // ids 0..visual.positions.size()-1 are visual vertices
    int globalIdCount = 0;                        // visual vertices plus inner (extruded) vertices
    MassProperties mass;                          // sum over primitives, in mesh coordinates
                                                  // (overlapping primitives count twice)
    double thickness = 0.0;                       // the thickness actually used
    double density = 0.0;
    double contactTolerance = 0.0;                // the contact tolerance actually used (m)
    // Visual vertex pairs (a < b), sorted: edges of the visual mesh along the artist's tear
    // lines (`tear.<body>` objects, TearLines.h). Connections across them may break.
    std::vector<std::pair<int, int>> tearEdges;
    std::vector<std::string> warnings;

    // Number of connected components of the primitive graph.
    int componentCount() const;
};

enum class JointType { Fixed, Hinge, Ball };

// A joint defined by a box in the OBJ file (source 000 §3.1), named
// `joint.<fixed|hinge|ball>.<bodyA>.<bodyB>[.anything]`.
struct JointBox {
    std::string name;
    JointType type = JointType::Fixed;
    std::string bodyA, bodyB;
    // Box frame in mesh coordinates: origin at the centre, columns of the rotation are the
    // box axes sorted by decreasing half-extent (a hinge turns about axis 0, the longest).
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    Eigen::Vector3d halfExtents = Eigen::Vector3d::Zero();
    // Primitives of each body that touch or overlap the box (fixed by the oriented-particle solver).
    std::vector<int> attachmentsA, attachmentsB;
};

struct PhysicalObject {
    std::vector<PhysicalMesh> bodies;
    std::vector<JointBox> joints;
    std::vector<std::string> warnings;
    // Index of the body with that name, or -1.
    int findBody(const std::string& name) const;
};

// Builds the physical mesh of one body from polygon faces over `positions`.
// Closed convex connected parts become single primitives; every other face is extruded
// (non-planar or non-convex polygons are split into triangles first). Throws
// shatter::InputError naming `name` for a non-positive or non-finite thickness, density or
// tolerance, or when no face is left.
// Details: thickness and contactTolerance 0 pick the defaults; a face index out of range or
// a non-finite position used by a face is an error; degenerate faces (fewer than 3
// distinct vertices, a vertex repeated, zero area) are skipped with one warning. Parts are
// found by welding vertices with identical coordinates; a closed convex part wound inward is
// flipped (its visual faces too) with a warning. visual.faces holds the kept faces (repeated
// consecutive vertices removed) and sourceFace indexes them.
PhysicalMesh buildPhysicalMesh(const std::string& name, const std::vector<Eigen::Vector3d>& positions,
                               const std::vector<std::vector<int>>& faces, const PhysicalMeshSettings& settings = {});

// Builds all bodies and joints of an OBJ file. Objects whose names share the part before
// the first '.' form one body (`door`, `door.handle`); `joint.*` objects become joints;
// the polylines of a `tear.<body>` object become that body's tearEdges (TearLines.h).
// Details: bodies come in order of their first object; each body's visual mesh holds only
// the vertices its faces use (in file order) and its messages name faces by "path:line".
// A joint box must be a box (see fitBox in JointBoxes.h) between two existing, different
// bodies; errors name the file and line of its `o`/`g`. Attachments are the primitives
// within the body's contact tolerance of the box. warnings = the file's warnings, then each
// body's (prefixed "body 'name': "), then joints touching no primitive of a body.
PhysicalObject buildPhysicalObject(const ObjFile& file, const PhysicalMeshSettings& settings = {});

} // namespace shatter::geometry
