#include <shatter/plugin/geometry/JointBoxes.h>

#include <shatter/plugin/common/InputError.h>
#include <shatter/plugin/geometry/Polygon.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>
#include <sstream>

namespace shatter::geometry {

namespace {

std::vector<std::string> splitOnDots(const std::string& s) {
    std::vector<std::string> parts;
    size_t start = 0;
    while (true) {
        const size_t dot = s.find('.', start);
        parts.push_back(s.substr(start, dot == std::string::npos ? std::string::npos : dot - start));
        if (dot == std::string::npos) return parts;
        start = dot + 1;
    }
}

[[noreturn]] void notABox(const std::string& where, const std::string& reason) {
    throw InputError(where + ": not a box (" + reason + ")");
}

// Face normals grouped into directions (up to sign), with the area-weighted mean direction.
struct Direction {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero(); // Σ area vectors, signs aligned
    std::vector<int> faces;
    Eigen::Vector3d unit() const { return sum.normalized(); }
};

std::vector<Direction> groupNormals(const std::vector<Eigen::Vector3d>& points,
                                    const std::vector<std::vector<int>>& faces, double angleTolerance,
                                    const std::string& where) {
    std::vector<Direction> directions;
    for (size_t f = 0; f < faces.size(); ++f) {
        const Eigen::Vector3d a = polygonAreaVector(points, faces[f]);
        if (!(a.norm() > 0.0)) notABox(where, "a face has zero area");
        const Eigen::Vector3d n = a.normalized();
        auto match = std::find_if(directions.begin(), directions.end(), [&](const Direction& d) {
            return n.cross(d.unit()).norm() <= angleTolerance;
        });
        if (match == directions.end()) {
            directions.emplace_back();
            match = directions.end() - 1;
        }
        match->sum += match->sum.dot(a) < 0.0 ? Eigen::Vector3d(-a) : a;
        match->faces.push_back(int(f));
    }
    return directions;
}

// Orthonormal right-handed frame from three nearly orthogonal directions, the one with
// the most face area kept exactly.
Eigen::Matrix3d orthonormalFrame(std::vector<Direction> d) {
    std::stable_sort(d.begin(), d.end(), [](const Direction& a, const Direction& b) { return a.sum.norm() > b.sum.norm(); });
    Eigen::Matrix3d r;
    r.col(0) = d[0].unit();
    r.col(1) = (d[1].unit() - d[1].unit().dot(r.col(0)) * r.col(0)).normalized();
    r.col(2) = r.col(0).cross(r.col(1));
    return r;
}

struct Extent {
    double lo = INFINITY, hi = -INFINITY;
};

// Checks that every face lies on one side of the box and that the faces on each side
// cover it exactly once (by area).
void checkSurface(const std::vector<Eigen::Vector3d>& points, const std::vector<std::vector<int>>& faces,
                  const Eigen::Matrix3d& axes, const std::array<Extent, 3>& extent, double tol,
                  const std::string& where) {
    std::array<double, 6> covered{}; // side 2·axis + (0 low, 1 high)
    for (const auto& face : faces) {
        const Eigen::Vector3d a = polygonAreaVector(points, face);
        int axis = 0;
        (axes.transpose() * a).cwiseAbs().maxCoeff(&axis);
        const bool high = axes.col(axis).dot(a) > 0.0;
        const double plane = high ? extent[axis].hi : extent[axis].lo;
        for (int v : face)
            if (std::abs(axes.col(axis).dot(points[v]) - plane) > tol)
                notABox(where, "a vertex lies off the box surface");
        covered[2 * axis + (high ? 1 : 0)] += 0.5 * a.norm();
    }
    for (int axis = 0; axis < 3; ++axis) {
        const int u = (axis + 1) % 3, v = (axis + 2) % 3;
        const double du = extent[u].hi - extent[u].lo, dv = extent[v].hi - extent[v].lo;
        const double expected = du * dv;
        const double allowed = 1e-6 * expected + 2.0 * tol * (du + dv);
        for (int side = 0; side < 2; ++side)
            if (std::abs(covered[2 * axis + side] - expected) > allowed)
                notABox(where, "the faces do not cover each side of the box exactly once");
    }
}

// Sign of a box axis, fixed so that the same box gives the same frame: its largest
// component is positive.
Eigen::Vector3d canonicalSign(const Eigen::Vector3d& axis) {
    int largest = 0;
    axis.cwiseAbs().maxCoeff(&largest);
    return axis[largest] < 0.0 ? Eigen::Vector3d(-axis) : axis;
}

} // namespace

bool isJointName(const std::string& objectName) { return objectName.rfind("joint.", 0) == 0; }

JointBox parseJointName(const std::string& objectName, const std::string& where) {
    const std::vector<std::string> parts = splitOnDots(objectName);
    const std::string prefix = where + ": joint '" + objectName + "': ";
    if (parts.size() < 4 || parts[2].empty() || parts[3].empty())
        throw InputError(prefix + "the name needs the form joint.<fixed|hinge|ball>.<bodyA>.<bodyB>");
    JointBox joint;
    joint.name = objectName;
    if (parts[1] == "fixed") joint.type = JointType::Fixed;
    else if (parts[1] == "hinge") joint.type = JointType::Hinge;
    else if (parts[1] == "ball") joint.type = JointType::Ball;
    else throw InputError(prefix + "unknown joint type '" + parts[1] + "' (expected fixed, hinge or ball)");
    joint.bodyA = parts[2];
    joint.bodyB = parts[3];
    if (joint.bodyA == joint.bodyB) throw InputError(prefix + "joins body '" + joint.bodyA + "' to itself");
    return joint;
}

OrientedBox fitBox(const std::vector<Eigen::Vector3d>& points, const std::vector<std::vector<int>>& faces,
                   const std::string& where) {
    Aabb bounds;
    for (const auto& face : faces)
        for (int v : face) bounds.extend(points[v]);
    const double tol = std::max(1e-6 * bounds.diagonal(), 1e-6);
    // A vertex error of tol tilts a face normal by up to about 2·tol over the face size.
    double smallest = INFINITY;
    for (int axis = 0; axis < 3; ++axis) smallest = std::min(smallest, bounds.extent()[axis]);
    const double angleTolerance = 1e-6 + 2.0 * tol / std::max(smallest, 1e3 * tol);

    const std::vector<Direction> directions = groupNormals(points, faces, angleTolerance, where);
    if (directions.size() != 3) {
        std::ostringstream reason;
        reason << "the face normals point in " << directions.size() << " directions, a box has 3";
        notABox(where, reason.str());
    }
    for (int i = 0; i < 3; ++i)
        for (int j = i + 1; j < 3; ++j)
            if (std::abs(directions[i].unit().dot(directions[j].unit())) > angleTolerance)
                notABox(where, "the face directions are not mutually orthogonal");
    const Eigen::Matrix3d axes = orthonormalFrame(directions);

    std::array<Extent, 3> extent;
    for (const auto& face : faces)
        for (int v : face)
            for (int axis = 0; axis < 3; ++axis) {
                const double p = axes.col(axis).dot(points[v]);
                extent[axis].lo = std::min(extent[axis].lo, p);
                extent[axis].hi = std::max(extent[axis].hi, p);
            }
    for (const auto& e : extent)
        if (!(e.hi - e.lo > 2.0 * tol)) notABox(where, "it is flat");
    checkSurface(points, faces, axes, extent, tol, where);

    std::array<int, 3> order{0, 1, 2};
    std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
        return extent[a].hi - extent[a].lo > extent[b].hi - extent[b].lo;
    });
    OrientedBox box;
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();
    for (int axis = 0; axis < 3; ++axis) centre += 0.5 * (extent[axis].lo + extent[axis].hi) * axes.col(axis);
    Eigen::Matrix3d r;
    r.col(0) = canonicalSign(axes.col(order[0]));
    r.col(1) = canonicalSign(axes.col(order[1]));
    r.col(2) = r.col(0).cross(r.col(1));
    for (int k = 0; k < 3; ++k) box.halfExtents[k] = 0.5 * (extent[order[k]].hi - extent[order[k]].lo);
    box.pose.linear() = r;
    box.pose.translation() = centre;
    return box;
}

ConvexPolyhedron boxPolyhedron(const OrientedBox& box) {
    std::vector<Eigen::Vector3d> corners;
    for (int i = 0; i < 8; ++i) {
        const Eigen::Vector3d local((i & 1 ? 1.0 : -1.0) * box.halfExtents.x(), (i & 2 ? 1.0 : -1.0) * box.halfExtents.y(),
                                    (i & 4 ? 1.0 : -1.0) * box.halfExtents.z());
        corners.push_back(box.pose * local);
    }
    std::vector<std::vector<int>> faces = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    return ConvexPolyhedron::create(std::move(corners), std::move(faces), {0, 1, 2, 3, 4, 5, 6, 7}, "joint box");
}

} // namespace shatter::geometry
