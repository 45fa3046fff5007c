// An OBJ file as bodies and joints (source 000 §3.1): objects sharing the name part before
// the first '.' form one body; `joint.*` objects are boxes that define joints.
#include <shatter/plugin/geometry/Connectivity.h>
#include <shatter/plugin/common/InputError.h>
#include <shatter/plugin/geometry/JointBoxes.h>
#include <shatter/plugin/geometry/PhysicalMeshBuilder.h>
#include <shatter/plugin/geometry/TearLines.h>

#include <algorithm>

namespace shatter::geometry {

namespace {

std::string bodyNameOf(const std::string& objectName) { return objectName.substr(0, objectName.find('.')); }

std::string where(const ObjFile& file, int line) { return file.path + ":" + std::to_string(line); }

struct BodyObjects {
    std::string name;
    std::vector<const ObjObject*> objects;
};

// Bodies in order of their first object.
std::vector<BodyObjects> groupBodies(const ObjFile& file) {
    std::vector<BodyObjects> bodies;
    for (const auto& object : file.objects) {
        // Joint boxes and tear lines belong to bodies; an object of other polylines only is
        // no body (polylines outside `tear.*` objects are ignored, as they always were).
        if (isJointName(object.name) || isTearName(object.name) || object.faces.empty()) continue;
        const std::string name = bodyNameOf(object.name);
        if (name.empty())
            throw InputError(where(file, object.line) + ": object '" + object.name +
                             "' has no body name before its first '.'");
        auto it = std::find_if(bodies.begin(), bodies.end(), [&](const BodyObjects& b) { return b.name == name; });
        if (it == bodies.end()) it = bodies.insert(bodies.end(), {name, {}});
        it->objects.push_back(&object);
    }
    return bodies;
}

// A body's own vertices (in file order) and its faces over them, labelled "file:line".
PhysicalMesh buildBody(const ObjFile& file, const BodyObjects& body, const PhysicalMeshSettings& settings) {
    std::vector<int> local(file.positions.size(), -1);
    std::vector<int> used;
    for (const ObjObject* object : body.objects)
        for (const auto& face : object->faces) used.insert(used.end(), face.vertices.begin(), face.vertices.end());
    std::sort(used.begin(), used.end());
    used.erase(std::unique(used.begin(), used.end()), used.end());
    std::vector<Eigen::Vector3d> positions;
    for (int v : used) {
        local[v] = int(positions.size());
        positions.push_back(file.positions[v]);
    }
    std::vector<std::vector<int>> faces;
    std::vector<std::string> labels;
    for (const ObjObject* object : body.objects)
        for (const auto& face : object->faces) {
            std::vector<int> polygon;
            for (int v : face.vertices) polygon.push_back(local[v]);
            faces.push_back(std::move(polygon));
            labels.push_back(where(file, face.line));
        }
    return buildLabelledPhysicalMesh(body.name, positions, faces, labels, settings);
}

std::string bodyList(const PhysicalObject& object) {
    std::string out;
    for (const auto& body : object.bodies) out += (out.empty() ? "" : ", ") + body.name;
    return out;
}

JointBox buildJoint(const ObjFile& file, const ObjObject& box, PhysicalObject& object) {
    const std::string at = where(file, box.line);
    JointBox joint = parseJointName(box.name, at);
    const std::string prefix = at + ": joint '" + box.name + "'";
    for (const std::string& body : {joint.bodyA, joint.bodyB})
        if (object.findBody(body) < 0)
            throw InputError(prefix + ": body '" + body + "' does not exist (bodies: " + bodyList(object) + ")");
    std::vector<std::vector<int>> faces;
    for (const auto& face : box.faces) faces.push_back(face.vertices);
    const OrientedBox fitted = fitBox(file.positions, faces, prefix);
    joint.pose = fitted.pose;
    joint.halfExtents = fitted.halfExtents;
    const ConvexPolyhedron solid = boxPolyhedron(fitted);
    auto attach = [&](const std::string& name, std::vector<int>& attachments) {
        const PhysicalMesh& mesh = object.bodies[object.findBody(name)];
        attachments = primitivesTouching(mesh.primitives, solid, mesh.contactTolerance);
        if (attachments.empty())
            object.warnings.push_back(prefix + ": touches no primitive of body '" + name + "'");
    };
    attach(joint.bodyA, joint.attachmentsA);
    attach(joint.bodyB, joint.attachmentsB);
    return joint;
}

} // namespace

int PhysicalObject::findBody(const std::string& name) const {
    for (size_t i = 0; i < bodies.size(); ++i)
        if (bodies[i].name == name) return int(i);
    return -1;
}

PhysicalObject buildPhysicalObject(const ObjFile& input, const PhysicalMeshSettings& settings) {
    // Coordinates in metres first: bodies and joint boxes alike.
    settings.check(input.path);
    ObjFile file = input;
    for (Eigen::Vector3d& p : file.positions) p *= settings.metresPerInputUnit();
    PhysicalMeshSettings inMetres = settings;
    inMetres.units = LengthUnit::Metres;
    inMetres.scale = 1.0;
    PhysicalObject object;
    object.warnings = file.warnings;
    for (const auto& body : groupBodies(file)) {
        object.bodies.push_back(buildBody(file, body, inMetres));
        const auto& warnings = object.bodies.back().warnings;
        object.warnings.insert(object.warnings.end(), warnings.begin(), warnings.end());
    }
    if (object.bodies.empty()) throw InputError(file.path + ": no bodies (only joint boxes)");
    for (const auto& box : file.objects)
        if (isJointName(box.name)) object.joints.push_back(buildJoint(file, box, object));
    for (const auto& tear : file.objects)
        if (isTearName(tear.name)) addTearLines(file, tear, object);
    return object;
}

} // namespace shatter::geometry
