#include <shatter/plugin/oriented/PlasticDeformation.h>

#include <shatter/plugin/common/InputError.h>
#include <shatter/plugin/common/SettingCheck.h>

#include <cmath>
#include <sstream>

namespace shatter::oriented {

void PlasticSettings::check(const std::string& body) const {
    requireNonNegative(body, "plastic threshold (m/s)", threshold);
    requireAtLeast(body, "plastic rings", rings, 1);
    requireAtLeast(body, "plastic sweeps", sweeps, 1);
}

namespace {

// Longest offset per particle, checked.
std::vector<Eigen::Vector3d> offsetsPerParticle(const OrientedSolver& solver, std::span<const Dent> dents) {
    std::vector<Eigen::Vector3d> offset(solver.particles().size(), Eigen::Vector3d::Zero());
    for (const Dent& d : dents) {
        if (d.particle < 0 || d.particle >= solver.particles().size() || !d.offset.allFinite()) {
            std::ostringstream msg;
            msg << "object '" << solver.object() << "': dent on particle " << d.particle
                << (d.offset.allFinite() ? " names a particle the object does not have" : " has a non-finite offset");
            throw InputError(msg.str());
        }
        if (d.offset.squaredNorm() > offset[d.particle].squaredNorm()) offset[d.particle] = d.offset;
    }
    return offset;
}

// Graph distance (in rings) from the nearest dented particle, up to `rings`; -1 beyond.
std::vector<int> ringsFrom(const ShapeMatchingGroups& groups, const std::vector<int>& seeds, int rings) {
    std::vector<int> ring(groups.size(), -1);
    std::vector<int> frontier = seeds, next;
    for (int s : seeds) ring[s] = 0;
    for (int r = 1; r <= rings && !frontier.empty(); ++r) {
        next.clear();
        for (int i : frontier)
            for (int j : groups.members(i))
                if (ring[j] < 0) {
                    ring[j] = r;
                    next.push_back(j);
                }
        frontier.swap(next);
    }
    return ring;
}

} // namespace

PlasticResult deformPlastically(OrientedSolver& solver, std::span<const Dent> dents, const PlasticSettings& settings) {
    settings.check(solver.object());
    const std::vector<Eigen::Vector3d> offset = offsetsPerParticle(solver, dents);
    OrientedParticles& p = solver.particles();
    const std::vector<bool> jointFixed = p.fixed;

    std::vector<int> hit;
    for (int i = 0; i < p.size(); ++i)
        if (offset[i].squaredNorm() > 0.0 && !jointFixed[i]) hit.push_back(i);
    PlasticResult result;
    if (hit.empty()) return result;

    // Hit primitives are held at their pushed positions and the outer ring at rest: the
    // solver rearranges what lies between (the source's boundary conditions, plus locality).
    const std::vector<int> ring = ringsFrom(solver.groups(), hit, settings.rings);
    std::vector<int> relaxed;
    for (int i = 0; i < p.size(); ++i) {
        if (ring[i] < 0) continue;
        if (ring[i] == 0) {
            p.position[i] += offset[i];
            p.fixed[i] = true;
        } else if (ring[i] == settings.rings) {
            p.fixed[i] = true;
        } else if (!jointFixed[i]) {
            relaxed.push_back(i);
        }
    }
    std::vector<int> active = relaxed;
    active.insert(active.end(), hit.begin(), hit.end());
    solver.relax(relaxed, settings.sweeps);
    // Held primitives turn with their neighbourhood, as the relaxed ones did.
    for (int i : hit)
        p.orientation[i] = solver.groups().fitRotation(i, p, p.position, p.orientation, solver.settings().rotationIterations);

    for (int i : active) {
        const Eigen::Matrix3d R = p.orientation[i].toRotationMatrix();
        Eigen::Isometry3d motion = Eigen::Isometry3d::Identity();
        motion.linear() = R;
        motion.translation() = p.position[i] - R * p.restPosition[i];
        result.maxDisplacement = std::max(result.maxDisplacement, (p.position[i] - p.restPosition[i]).norm());
        result.moved.push_back(i);
        result.motion.push_back(motion);
        p.restPosition[i] = p.position[i];
        p.restMoment[i] = R * p.restMoment[i] * R.transpose();
        p.orientation[i] = Eigen::Quaterniond::Identity();
    }
    p.fixed = jointFixed;
    solver.groups().updateRest(p);
    return result;
}

} // namespace shatter::oriented
