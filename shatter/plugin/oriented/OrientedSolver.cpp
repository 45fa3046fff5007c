#include <shatter/plugin/oriented/OrientedSolver.h>

#include <shatter/plugin/common/InputError.h>

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
Eigen::Vector3d velocityFrom(const Eigen::Vector3d& change, const Eigen::Vector3d& lastChange, double dt,
                             bool secondOrder) {
    if (!secondOrder) return change / dt;
    return (3.0 * change - lastChange) / (2.0 * dt);
}

} // namespace

OrientedSolver::OrientedSolver(std::string object, OrientedParticles particles,
                               const std::vector<std::pair<int, int>>& connections, const SolverSettings& settings)
    : object_(std::move(object)), particles_(std::move(particles)), groups_(particles_, connections),
      settings_(settings) {
    settings_.check(object_);
}

void OrientedSolver::setSettings(const SolverSettings& settings) {
    settings.check(object_);
    settings_ = settings;
}

void OrientedSolver::step(double dt, std::span<const ParticleContact> contacts) {
    if (!(std::isfinite(dt) && dt > 0.0)) {
        std::ostringstream msg;
        msg << "object '" << object_ << "': time step must be finite and > 0, got " << dt;
        throw InputError(msg.str());
    }
    checkContacts(contacts);
    separate(contacts);
    predict(dt);
    // Warm-start each group's fit with its centre's predicted turn: a rigidly spinning
    // group then starts at its answer, and the fit does not lag behind (and brake) the spin.
    for (int g = 0; g < groups_.size(); ++g) {
        const int c = groups_.members(g)[0];
        const Eigen::Quaterniond turn = predictedOrientation_[c] * startOrientation_[c].conjugate();
        groups_.setRotation(g, (turn * groups_.rotation(g)).normalized());
    }
    contactPush_.assign(contacts.size(), 0.0);
    for (int sweep = 0; sweep < settings_.iterations; ++sweep) {
        for (const auto& c : stretch_) c.project(particles_, predicted_);
        for (const auto& c : bend_) c.project(particles_, predictedOrientation_);
        for (int g = 0; g < groups_.size(); ++g)
            groups_.project(g, particles_, predicted_, predictedOrientation_, settings_.stiffness,
                            settings_.rotationIterations);
        // Contacts last, so the step ends with no particle through a surface and with
        // friction having the last word on sliding.
        projectContacts(contacts);
    }
    updateVelocities(dt);
}

void OrientedSolver::checkContacts(std::span<const ParticleContact> contacts) const {
    for (size_t k = 0; k < contacts.size(); ++k) {
        const ParticleContact& c = contacts[k];
        const char* problem = nullptr;
        if (c.particle < 0 || c.particle >= particles_.size()) problem = "names a particle the object does not have";
        else if (!c.normal.allFinite() || !std::isfinite(c.distance) || !std::isfinite(c.friction))
            problem = "has a non-finite normal, distance or friction";
        else if (std::abs(c.normal.norm() - 1.0) > 1e-6) problem = "has a normal that is not of unit length";
        if (problem) {
            std::ostringstream msg;
            msg << "object '" << object_ << "': contact " << k << " (particle " << c.particle << ") " << problem;
            throw InputError(msg.str());
        }
    }
}

void OrientedSolver::separate(std::span<const ParticleContact> contacts) {
    // Pre-stabilisation (Macklin et al. 2014): a particle that starts the step inside a
    // surface is moved out before the step, start position included, so that resolving the
    // overlap adds no velocity (a PBD contact that pushes out during the step would launch
    // the particle at overlap/dt, and a resting body would jitter).
    contactGap_.resize(contacts.size());
    std::vector<Eigen::Vector3d> shift(particles_.size(), Eigen::Vector3d::Zero());
    for (size_t k = 0; k < contacts.size(); ++k) {
        const ParticleContact& c = contacts[k];
        const double overlap = -(c.distance + c.normal.dot(shift[c.particle]));
        if (overlap > 0.0 && !particles_.fixed[c.particle]) shift[c.particle] += overlap * c.normal;
    }
    for (int i = 0; i < particles_.size(); ++i) particles_.position[i] += shift[i];
    for (size_t k = 0; k < contacts.size(); ++k)
        contactGap_[k] = contacts[k].distance + contacts[k].normal.dot(shift[contacts[k].particle]);
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

void OrientedSolver::projectContacts(std::span<const ParticleContact> contacts) {
    for (size_t k = 0; k < contacts.size(); ++k) {
        const ParticleContact& c = contacts[k];
        const int i = c.particle;
        if (particles_.fixed[i]) continue;
        const Eigen::Vector3d move = predicted_[i] - startPosition_[i];
        const double push = -(c.normal.dot(move) + contactGap_[k]);
        if (push > 0.0) {
            predicted_[i] += push * c.normal;
            contactPush_[k] += push;
        }
        if (contactPush_[k] == 0.0) continue; // not touching in this step: no friction
        // Position-based Coulomb friction: this step's tangential move is cancelled when it
        // is within friction × the step's normal correction (static), else shortened by that.
        const Eigen::Vector3d tangential = move - c.normal.dot(move) * c.normal;
        const double length = tangential.norm(), budget = c.friction * contactPush_[k];
        if (length <= budget) predicted_[i] -= tangential;
        else predicted_[i] -= budget / length * tangential;
    }
}

void OrientedSolver::updateVelocities(double dt) {
    auto& p = particles_;
    const int n = p.size();
    const bool secondOrder = settings_.secondOrderVelocity && haveLastStep_;
    lastStep_.resize(n, Eigen::Vector3d::Zero());
    lastTurn_.resize(n, Eigen::Vector3d::Zero());
    const double keep = std::exp(-settings_.damping * dt);
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
    }
    haveLastStep_ = true;
}

void OrientedSolver::relax(std::span<const int> groups, int sweeps) {
    for (int sweep = 0; sweep < sweeps; ++sweep)
        for (int g : groups)
            groups_.project(g, particles_, particles_.position, particles_.orientation, 1.0,
                            settings_.rotationIterations);
}

Eigen::Matrix3d OrientedSolver::deformation(int i) const {
    return groups_.deformation(i, particles_, particles_.position, particles_.orientation);
}

} // namespace shatter::oriented
