#include <shatter/plugin/oriented/OrientedSolver.h>

#include <shatter/plugin/common/InputError.h>

#include <algorithm>
#include <cmath>
#include <sstream>

namespace shatter::oriented {

namespace {

// Rotation vector (axis × angle) of the shortest arc from `from` to `to`.
Eigen::Vector3d rotationBetween(const Eigen::Quaterniond& from, const Eigen::Quaterniond& to) {
    Eigen::Quaterniond turn = to * from.conjugate();
    if (turn.w() < 0.0) turn.coeffs() = -turn.coeffs(); // q and −q are the same rotation
    const double sine = turn.vec().norm();
    if (sine == 0.0) return Eigen::Vector3d::Zero();
    return 2.0 * std::atan2(sine, turn.w()) / sine * turn.vec();
}

// First order: this step's change over dt. Second order (BDF2): (3 Δ_n − Δ_{n−1}) / 2dt.
// Always inlined: GCC called it (twice a particle a substep, the vectors through the stack).
[[gnu::always_inline]] inline Eigen::Vector3d velocityFrom(const Eigen::Vector3d& change,
                                                            const Eigen::Vector3d& lastChange, double dt,
                                                            bool secondOrder) {
    if (!secondOrder) return change / dt;
    return (3.0 * change - lastChange) / (2.0 * dt);
}

// A sweep's rotation fit ends after a Newton step under this (rad). The error it leaves is of
// order its square times a small constant (about 3e-11 rad measured: picometres across a
// group), and it is not kept: the next sweep's fit starts from this one's answer. Most
// warm-started first steps are 1e-4 to 1e-3 rad, so most fits take one evaluation, not two.
constexpr double kSweepNewtonStop = 1e-3;

// Chebyshev's weight ω of sweep `sweep` (from 0) for spectral radius ρ, from the last sweep's
// `last` (Wang 2015): 1, then 2/(2 − ρ²), then 4/(4 − ρ² ω_last).
double chebyshevWeight(double rho, int sweep, double last) {
    const double rho2 = rho * rho;
    if (sweep == 0) return 1.0;
    if (sweep == 1) return 2.0 / (2.0 - rho2);
    return 4.0 / (4.0 - rho2 * last);
}

} // namespace

OrientedSolver::OrientedSolver(std::string object, OrientedParticles particles,
                               const std::vector<std::pair<int, int>>& connections, const SolverSettings& settings)
    : object_(std::move(object)), particles_(std::move(particles)), groups_(particles_, connections),
      settings_(settings) {
    settings_.check(object_);
}

void OrientedSolver::rebuild(std::string object, OrientedParticles particles,
                             const std::vector<std::pair<int, int>>& connections, const SolverSettings& settings) {
    settings.check(object);
    groups_.rebuild(particles, connections);
    object_ = std::move(object);
    particles_ = std::move(particles);
    settings_ = settings;
    stretch_.clear();
    bend_.clear();
    // The per-step buffers as a new solver's: empty (their capacity stays).
    for (auto* v : {&startPosition_, &predicted_, &lastStep_, &lastTurn_, &contactPush_, &contactImpulses_, &separation_, &found_})
        v->clear();
    startOrientation_.clear();
    predictedOrientation_.clear();
    contactImpulse_.clear();
    contactGap_.clear();
    contactDistance_.clear();
    haveLastStep_ = false;
    quietTime_ = 0.0;
}

void OrientedSolver::setSettings(const SolverSettings& settings) {
    settings.check(object_);
    settings_ = settings;
}

void OrientedSolver::step(double dt, std::span<const ParticleContact> contacts, std::span<ContactBody> bodies,
                          int substeps) {
    if (!(std::isfinite(dt) && dt > 0.0)) {
        std::ostringstream msg;
        msg << "object '" << object_ << "': time step must be finite and > 0, got " << dt;
        throw InputError(msg.str());
    }
    if (substeps < 1) {
        std::ostringstream msg;
        msg << "object '" << object_ << "': substeps must be >= 1, got " << substeps;
        throw InputError(msg.str());
    }
    checkContacts(contacts, bodies, substeps);
    for (ContactBody& b : bodies) b.shift.setZero(), b.turn.setZero();
    if (substeps > 1) found_ = particles_.position;
    contactImpulses_.assign(contacts.size(), Eigen::Vector3d::Zero());
    for (int s = 0; s < substeps; ++s) substep(dt, contacts, bodies, s > 0);
}

void OrientedSolver::substep(double dt, std::span<const ParticleContact> contacts, std::span<ContactBody> bodies,
                             bool later) {
    separate(contacts, later);
    predict(dt);
    // Warm-start each group's fit with its centre's predicted turn: a rigidly spinning
    // group then starts at its answer, and the fit does not lag behind (and brake) the spin.
    for (int g = 0; g < groups_.size(); ++g) {
        const int c = groups_.members(g)[0];
        const Eigen::Quaterniond turn = predictedOrientation_[c] * startOrientation_[c].conjugate();
        groups_.setRotation(g, (turn * groups_.rotation(g)).normalized());
    }
    contactImpulse_.assign(contacts.size(), 0.0);
    contactPush_.assign(contacts.size(), Eigen::Vector3d::Zero());
    groups_.refreshMoments(particles_, predictedOrientation_, settings_.simdPath);
    // Between sweeps only the contacts move particles, unless pair constraints do: the sweeps
    // then run as one run (ShapeMatchingGroups::projectAllInRun) that keeps its padded copy of
    // the positions and copies only the contacts' particles out and back in between.
    // Accelerated sweeps (SolverSettings::chebyshevRadius) always run as one run, which keeps
    // the last sweep's motion; with pair constraints every particle counts as touched.
    const bool accelerated = settings_.chebyshevRadius > 0.0;
    const bool pairs = !stretch_.empty() || !bend_.empty();
    const bool run = !pairs || accelerated;
    if (run) {
        touched_.clear();
        if (pairs)
            for (int i = 0; i < particles_.size(); ++i) touched_.push_back(i);
        else
            for (const ParticleContact& c : contacts) {
                touched_.push_back(c.particle);
                if (c.otherParticle >= 0) touched_.push_back(c.otherParticle);
            }
    }
    double omega = 0.0;
    for (int sweep = 0; sweep < settings_.iterations; ++sweep) {
        if (accelerated) omega = chebyshevWeight(settings_.chebyshevRadius, sweep, omega);
        for (const auto& c : stretch_) c.project(particles_, predicted_);
        for (const auto& c : bend_) c.project(particles_, predictedOrientation_);
        // Groups keep the cached moments current for the turns they make; bend constraints
        // turn particles behind their back.
        if (!bend_.empty()) groups_.refreshMoments(particles_, predictedOrientation_, settings_.simdPath);
        if (run)
            groups_.projectAllInRun(particles_, predicted_, predictedOrientation_, settings_.stiffness,
                                    settings_.rotationIterations, kSweepNewtonStop, settings_.simdPath, sweep == 0,
                                    sweep + 1 == settings_.iterations, touched_, omega);
        else
            groups_.projectAll(particles_, predicted_, predictedOrientation_, settings_.stiffness,
                               settings_.rotationIterations, kSweepNewtonStop, settings_.simdPath);
        // Contacts last, so the step ends with no particle through a surface and with
        // friction having the last word on sliding.
        projectContacts(contacts, bodies);
    }
    updateVelocities(dt);
    for (size_t k = 0; k < contacts.size(); ++k) contactImpulses_[k] += contactPush_[k] / dt;
}

void OrientedSolver::checkContacts(std::span<const ParticleContact> contacts, std::span<const ContactBody> bodies,
                                   int substeps) const {
    for (size_t k = 0; k < bodies.size(); ++k) {
        const ContactBody& b = bodies[k];
        if (std::isfinite(b.inverseMass) && b.inverseMass >= 0.0 && b.inverseInertia.allFinite() && b.centre.allFinite())
            continue;
        std::ostringstream msg;
        msg << "object '" << object_ << "': contact body " << k
            << " has a negative or non-finite inverse mass, or a non-finite inertia or centre";
        throw InputError(msg.str());
    }
    for (size_t k = 0; k < contacts.size(); ++k) {
        const ParticleContact& c = contacts[k];
        const char* problem = nullptr;
        if (c.particle < 0 || c.particle >= particles_.size()) problem = "names a particle the object does not have";
        else if (!c.normal.allFinite() || !std::isfinite(c.distance) || !std::isfinite(c.friction) ||
                 !c.point.allFinite() || !c.surfaceMove.allFinite())
            problem = "has a non-finite normal, distance, friction, point or surface motion";
        else if (std::abs(c.normal.norm() - 1.0) > 1e-6) problem = "has a normal that is not of unit length";
        else if (c.body >= int(bodies.size()) || c.body < -1) problem = "names a contact body that was not given";
        else if (c.otherParticle >= particles_.size() || c.otherParticle < -1 || c.otherParticle == c.particle)
            problem = "names another particle the object does not have";
        else if (c.body >= 0 && c.otherParticle >= 0) problem = "names both a body and another particle";
        else if (substeps > 1 && (c.body >= 0 || !c.surfaceMove.isZero(0.0)))
            problem = "names a body or a moving surface in a step of several substeps";
        if (problem) {
            std::ostringstream msg;
            msg << "object '" << object_ << "': contact " << k << " (particle " << c.particle << ") " << problem;
            throw InputError(msg.str());
        }
    }
}

void OrientedSolver::separate(std::span<const ParticleContact> contacts, bool later) {
    // Pre-stabilisation (Macklin et al. 2014): a particle that starts the step inside a
    // surface is moved out before the step, start position included, so that resolving the
    // overlap adds no velocity (a PBD contact that pushes out during the step would launch
    // the particle at overlap/dt, and a resting body would jitter). Two particles of the
    // object share the move by inverse mass; a body is not moved (its overlap is the
    // particle's to remove).
    // A later substep of a step meets its contacts where the earlier ones left the particles:
    // the distance found, plus their motion along the normal since (the other side stands still).
    contactGap_.resize(contacts.size());
    std::vector<Eigen::Vector3d>& shift = separation_;
    shift.assign(size_t(particles_.size()), Eigen::Vector3d::Zero());
    auto relativeShift = [&](const ParticleContact& c) {
        return c.normal.dot(shift[c.particle] - (c.otherParticle >= 0 ? shift[c.otherParticle] : Eigen::Vector3d::Zero()));
    };
    if (later) {
        const std::vector<Eigen::Vector3d>& x = particles_.position;
        auto moved = [&](int i) { return i >= 0 ? Eigen::Vector3d(x[i] - found_[i]) : Eigen::Vector3d::Zero(); };
        contactDistance_.resize(contacts.size());
        for (size_t k = 0; k < contacts.size(); ++k) {
            const ParticleContact& c = contacts[k];
            contactDistance_[k] = c.distance + c.normal.dot(moved(c.particle) - moved(c.otherParticle));
        }
    }
    auto distance = [&](size_t k) { return later ? contactDistance_[k] : contacts[k].distance; };
    for (size_t k = 0; k < contacts.size(); ++k) {
        const ParticleContact& c = contacts[k];
        const double overlap = -(distance(k) + relativeShift(c));
        if (overlap <= 0.0) continue;
        const double wa = inverseMass(c.particle), wb = c.otherParticle >= 0 ? inverseMass(c.otherParticle) : 0.0;
        if (wa + wb == 0.0) continue;
        shift[c.particle] += wa / (wa + wb) * overlap * c.normal;
        if (c.otherParticle >= 0) shift[c.otherParticle] -= wb / (wa + wb) * overlap * c.normal;
    }
    for (int i = 0; i < particles_.size(); ++i) particles_.position[i] += shift[i];
    for (size_t k = 0; k < contacts.size(); ++k) contactGap_[k] = distance(k) + relativeShift(contacts[k]);
}

void OrientedSolver::predict(double dt) {
    auto& p = particles_;
    const int n = p.size();
    startPosition_ = p.position;
    startOrientation_ = p.orientation;
    predicted_.resize(n);
    predictedOrientation_.resize(n);
    for (int i = 0; i < n; ++i) {
        predicted_[i] = p.position[i];
        predictedOrientation_[i] = p.orientation[i];
        if (p.fixed[i]) continue;
        p.velocity[i] += dt * settings_.gravity;
        predicted_[i] += dt * p.velocity[i];
        const double angle = p.angularVelocity[i].norm() * dt;
        if (angle > settings_.epsilon) {
            predictedOrientation_[i] =
                Eigen::Quaterniond(Eigen::AngleAxisd(angle, p.angularVelocity[i].normalized())) * p.orientation[i];
            predictedOrientation_[i].normalize();
        }
    }
}

// The other side of a contact as the projection sees it: where its contact point has gone in
// this step, how much it gives along a direction, and taking a correction.
struct OrientedSolver::Side {
    const ParticleContact& contact;
    ContactBody* body = nullptr;        // a coupled rigid body, or
    int particle = -1;                  // a particle of this object, or neither (a surface)
    double particleInverseMass = 0.0;
    Eigen::Vector3d arm = Eigen::Vector3d::Zero(); // body: contact point − centre

    Eigen::Vector3d move(const OrientedSolver& s) const {
        if (particle >= 0) return s.predicted_[particle] - s.startPosition_[particle];
        Eigen::Vector3d m = contact.surfaceMove;
        if (body) m += body->shift + body->turn.cross(arm);
        return m;
    }
    double inverseMass(const Eigen::Vector3d& d) const {
        if (particle >= 0) return particleInverseMass;
        if (!body) return 0.0;
        const Eigen::Vector3d lever = arm.cross(d);
        return body->inverseMass + lever.dot(body->inverseInertia * lever);
    }
    // Moves this side by −λ d / m (the particle side got +λ d / m).
    void take(OrientedSolver& s, const Eigen::Vector3d& d, double lambda) const {
        if (particle >= 0) s.predicted_[particle] -= particleInverseMass * lambda * d;
        if (!body) return;
        body->shift -= body->inverseMass * lambda * d;
        body->turn -= body->inverseInertia * arm.cross(d) * lambda;
    }
};

OrientedSolver::Side OrientedSolver::otherSide(const ParticleContact& c, std::span<ContactBody> bodies) const {
    Side side{c};
    if (c.otherParticle >= 0) {
        side.particle = c.otherParticle;
        side.particleInverseMass = inverseMass(c.otherParticle);
    } else if (c.body >= 0) {
        side.body = &bodies[size_t(c.body)];
        side.arm = c.point - side.body->centre;
    }
    return side;
}

void OrientedSolver::projectContacts(std::span<const ParticleContact> contacts, std::span<ContactBody> bodies) {
    for (size_t k = 0; k < contacts.size(); ++k) {
        const ParticleContact& c = contacts[k];
        const int i = c.particle;
        const Side other = otherSide(c, bodies);
        const double wa = inverseMass(i);
        const double wn = wa + other.inverseMass(c.normal);
        if (wn == 0.0) continue;
        // λ (kg m) moves the particle by wa λ n and the other side by −wb λ n: Σ m Δx = 0.
        const double gap = c.normal.dot(predicted_[i] - startPosition_[i] - other.move(*this)) + contactGap_[k];
        if (gap < 0.0) {
            const double lambda = -gap / wn;
            predicted_[i] += wa * lambda * c.normal;
            other.take(*this, c.normal, lambda);
            contactImpulse_[k] += lambda;
            contactPush_[k] += lambda * c.normal;
        }
        if (contactImpulse_[k] == 0.0) continue; // not touching in this step: no friction
        // Position-based Coulomb friction: this step's relative tangential move is cancelled
        // when that takes at most friction × the step's normal correction (static), else
        // shortened by that much.
        const Eigen::Vector3d relative = predicted_[i] - startPosition_[i] - other.move(*this);
        const Eigen::Vector3d tangential = relative - c.normal.dot(relative) * c.normal;
        const double length = tangential.norm();
        if (length == 0.0) continue;
        const Eigen::Vector3d direction = tangential / length;
        const double wt = wa + other.inverseMass(direction);
        const double lambda = std::min(length / wt, c.friction * contactImpulse_[k]);
        predicted_[i] -= wa * lambda * direction;
        other.take(*this, -direction, lambda);
        contactPush_[k] -= lambda * direction;
    }
}

void OrientedSolver::updateVelocities(double dt) {
    auto& p = particles_;
    const int n = p.size();
    const bool secondOrder = settings_.secondOrderVelocity && haveLastStep_;
    lastStep_.resize(n, Eigen::Vector3d::Zero());
    lastTurn_.resize(n, Eigen::Vector3d::Zero());
    const double keep = std::exp(-settings_.damping * dt);
    const double quietSpeed2 = settings_.sleepSpeed * settings_.sleepSpeed;
    bool quiet = settings_.sleepSpeed > 0.0;
    for (int i = 0; i < n; ++i) {
        if (p.fixed[i]) {
            p.velocity[i].setZero();
            p.angularVelocity[i].setZero();
            lastStep_[i].setZero();
            lastTurn_[i].setZero();
            continue;
        }
        const Eigen::Vector3d step = predicted_[i] - startPosition_[i];
        Eigen::Vector3d turn = rotationBetween(startOrientation_[i], predictedOrientation_[i]);
        if (turn.norm() <= settings_.epsilon) { // the source's threshold: no creeping spin
            turn.setZero();
            predictedOrientation_[i] = startOrientation_[i];
        }
        p.velocity[i] = keep * velocityFrom(step, lastStep_[i], dt, secondOrder);
        p.angularVelocity[i] = keep * velocityFrom(turn, lastTurn_[i], dt, secondOrder);
        p.position[i] = predicted_[i];
        p.orientation[i] = predictedOrientation_[i].normalized();
        lastStep_[i] = step;
        lastTurn_[i] = turn;
        if (quiet)
            quiet = p.velocity[i].squaredNorm() + p.angularVelocity[i].squaredNorm() * p.restMoment[i].trace() / p.mass[i] <
                    quietSpeed2;
    }
    haveLastStep_ = true;
    quietTime_ = quiet ? quietTime_ + dt : 0.0;
}

void OrientedSolver::stop() {
    auto& p = particles_;
    for (int i = 0; i < p.size(); ++i) p.velocity[i].setZero(), p.angularVelocity[i].setZero();
    haveLastStep_ = false;
    quietTime_ = 0.0;
}

void OrientedSolver::relax(std::span<const int> groups, int sweeps) {
    for (int sweep = 0; sweep < sweeps; ++sweep) {
        groups_.refreshMoments(particles_, particles_.orientation, settings_.simdPath);
        for (int g : groups)
            groups_.project(g, particles_, particles_.position, particles_.orientation, 1.0,
                            settings_.rotationIterations);
    }
}

Eigen::Matrix3d OrientedSolver::deformation(int i) const {
    return groups_.deformation(i, particles_, particles_.position, particles_.orientation);
}

} // namespace shatter::oriented
