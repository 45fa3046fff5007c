#include <shatter/bullet_ext/fracture/SubdivisionEvent.h>
#include <shatter/plugin/common/Stopwatch.h>

#include <shatter/bullet_ext/VisualBody.h>
#include <shatter/bullet_ext/oriented/PlasticDents.h>

#include <limits>

namespace shatter {

namespace {

// Moves each dent from its old primitive to that primitive's piece nearest to (or holding) its
// contact point. Pieces of one primitive are consecutive in the subdivided mesh.
void moveDentsToPieces(std::vector<oriented::Dent>& dents, const std::vector<Eigen::Vector3d>& points,
                       const fracture::SubdivisionResult& r) {
    for (size_t k = 0; k < dents.size(); ++k) {
        double nearest = std::numeric_limits<double>::infinity();
        int best = -1;
        for (size_t i = 0; i < r.parents.size(); ++i) {
            if (r.parents[i] != dents[k].particle) continue;
            const double d = r.mesh.primitives[i].signedDistance(points[k]);
            if (d < nearest) nearest = d, best = int(i);
        }
        dents[k].particle = best;
    }
}

} // namespace

SubdivisionOutcome subdivideInPlace(SystemContext& context, VisualBody& body, const fracture::FracturePattern& pattern,
                                    const fracture::Placement& where, const fracture::CutSettings& cut,
                                    const ContactSnapshot* contacts, double dt) {
    SubdivisionOutcome out;
    out.primitivesBefore = out.primitivesAfter = int(body.physicalMesh().primitives.size());
    std::vector<oriented::Dent> dents;
    std::vector<Eigen::Vector3d> points;
    if (contacts && body.deformation() == Deformation::Plastic) dents = findDents(*contacts, body, dt, &points);
    fracture::SubdivisionResult r = fracture::subdivideMesh(body.physicalMesh(), pattern, where, cut);
    out.cutSeconds = r.cutSeconds;
    out.assemblySeconds = r.assemblySeconds;
    out.primitivesCut = r.primitivesCut;
    if (r.primitivesCut == 0) return out;
    moveDentsToPieces(dents, points, r);
    const auto t = SteadyClock::now();
    oriented::PlasticResult dented;
    context.reshape(body, [&](CollisionFilter&) {
        body.subdivide(std::move(r.mesh), r.parents, r.kept);
        if (!dents.empty()) dented = body.dent(dents);
    });
    out.bodySeconds = secondsSince(t);
    out.primitivesAfter = int(body.physicalMesh().primitives.size());
    out.dented = int(dented.moved.size());
    context.push(EventType::BodySubdivided, body, out.primitivesAfter);
    if (out.dented > 0) context.push(EventType::BodyDented, body, out.dented);
    return out;
}

} // namespace shatter
