// shatter-bench-groupshape: the group shape against Bullet's btCompoundShape of
// btConvexHullShape on the same scene. A pile of chairs (each a group of box primitives) is
// dropped into a walled pit on a plane and stepped at a fixed 1/240 s (the default 600 steps
// cover the fall and the pile settling). Both shapes get the same geometry, masses, poses
// and solver, in one process, runs alternating. Prints per-run times, the median
// milliseconds per step of each and the ratio compound/group; the last stdout line is the
// same as JSON (also written to --json FILE).
#include <shatter/bullet_ext/Convert.h>
#include <shatter/bullet_ext/shape/GroupShape.h>

#include <btBulletDynamicsCommon.h>

#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <memory>
#include <random>
#include <sstream>
#include <string>
#include <unistd.h>
#include <vector>

namespace {

using shatter::geometry::ConvexPolyhedron;
using Primitives = std::vector<ConvexPolyhedron>;

struct Options {
    int bodies = 200;
    int steps = 600;
    int repeats = 5;
    int primitivesPerBody = 8;
    double margin = 0.04;
    std::string json;
    std::string only; // "group" or "compound" to run one side (for profiling)
};

ConvexPolyhedron box(const Eigen::Vector3d& centre, const Eigen::Vector3d& half) {
    std::vector<Eigen::Vector3d> v;
    for (int i = 0; i < 8; ++i)
        v.push_back(centre + Eigen::Vector3d(i & 1 ? half.x() : -half.x(), i & 2 ? half.y() : -half.y(),
                                             i & 4 ? half.z() : -half.z()));
    std::vector<std::vector<int>> f = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    return ConvexPolyhedron::create(std::move(v), std::move(f), {0, 1, 2, 3, 4, 5, 6, 7}, "chair part");
}

// A chair of `count` boxes (y up): seat, four legs, back, four stretchers, then vertical slats
// in front of the back. Lowest point at y = 0.
Primitives chair(int count) {
    std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> parts = {
        {{0, 0.45, 0}, {0.22, 0.02, 0.22}},       // seat
        {{-0.2, 0.215, -0.2}, {0.02, 0.215, 0.02}}, // legs
        {{0.2, 0.215, -0.2}, {0.02, 0.215, 0.02}},
        {{-0.2, 0.215, 0.2}, {0.02, 0.215, 0.02}},
        {{0.2, 0.215, 0.2}, {0.02, 0.215, 0.02}},
        {{0, 0.67, -0.205}, {0.22, 0.2, 0.015}},   // back
        {{-0.2, 0.12, 0}, {0.015, 0.015, 0.18}},   // stretchers
        {{0.2, 0.12, 0}, {0.015, 0.015, 0.18}},
        {{0, 0.12, -0.2}, {0.18, 0.015, 0.015}},
        {{0, 0.12, 0.2}, {0.18, 0.015, 0.015}},
    };
    Primitives p;
    for (int i = 0; i < count; ++i) {
        if (i < int(parts.size())) {
            p.push_back(box(parts[i].first, parts[i].second));
        } else { // slats, spread across the back
            const int k = i - int(parts.size());
            const double x = -0.2 + 0.4 * ((k * 0.618034) - std::floor(k * 0.618034));
            p.push_back(box({x, 0.67, -0.18}, {0.01, 0.18, 0.008}));
        }
    }
    return p;
}

// Primitives in their centre-of-mass principal frame, with mass and inertia at `density`.
struct Body {
    Primitives primitives;
    btTransform bodyToDesign;
    double mass;
    btVector3 inertia;
};
Body toBody(const Primitives& design, double density) {
    shatter::geometry::MassProperties total;
    for (const auto& p : design) total += p.massProperties(density);
    const auto principal = total.principal();
    Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
    t.linear() = principal.axes;
    t.translation() = total.centerOfMass;
    Body b;
    for (const auto& p : design) b.primitives.push_back(p.transformed(t.inverse()));
    b.bodyToDesign = shatter::toBullet(t);
    b.mass = total.mass;
    b.inertia = shatter::toBullet(principal.moments);
    return b;
}

enum class Kind { Group, Compound };

// One world: a plane, four walls, N chairs at seeded poses.
class Scene {
public:
    Scene(Kind kind, const Options& o) {
        world_.setGravity(btVector3(0, -9.81f, 0));
        if (kind == Kind::Group) shatter::registerGroupShapeAlgorithms(dispatcher_);
        addStatic(std::make_unique<btStaticPlaneShape>(btVector3(0, 1, 0), 0), btTransform::getIdentity());
        const int perRow = int(std::ceil(std::sqrt(o.bodies / 4.0)));
        const double spacing = 0.75;
        const double half = 0.5 * perRow * spacing + 0.1;
        for (int side = 0; side < 4; ++side) {
            const bool alongX = side < 2;
            const double s = side % 2 ? 1.0 : -1.0;
            const btVector3 extent = alongX ? btVector3(0.1f, 1.5f, btScalar(half + 0.2)) : btVector3(btScalar(half + 0.2), 1.5f, 0.1f);
            const btVector3 centre = alongX ? btVector3(btScalar(s * (half + 0.1)), 1.5f, 0) : btVector3(0, 1.5f, btScalar(s * (half + 0.1)));
            addStatic(std::make_unique<btBoxShape>(extent), btTransform(btQuaternion::getIdentity(), centre));
        }
        const Body body = toBody(chair(o.primitivesPerBody), 600.0);
        std::mt19937 rng(12345);
        std::uniform_real_distribution<double> angle(-M_PI, M_PI), tilt(-0.3, 0.3), jitter(-0.05, 0.05);
        for (int i = 0; i < o.bodies; ++i) {
            const int layer = i / (perRow * perRow), cell = i % (perRow * perRow);
            const btVector3 at(btScalar((cell % perRow + 0.5) * spacing - 0.5 * perRow * spacing + jitter(rng)),
                               btScalar(0.3 + layer * 0.95),
                               btScalar((cell / perRow + 0.5) * spacing - 0.5 * perRow * spacing + jitter(rng)));
            const btQuaternion q = btQuaternion(btVector3(0, 1, 0), btScalar(angle(rng))) *
                                   btQuaternion(btVector3(1, 0, 0), btScalar(tilt(rng)));
            addChair(kind, body, btTransform(q, at) * body.bodyToDesign, o.margin);
        }
    }
    ~Scene() {
        for (auto it = bodies_.rbegin(); it != bodies_.rend(); ++it) world_.removeRigidBody(it->get());
    }

    void step() { world_.stepSimulation(btScalar(1.0 / 240), 1, btScalar(1.0 / 240)); }

    // Mean speed of the chairs and their mean height: both variants should end in a similar pile.
    std::pair<double, double> state() const {
        double speed = 0, height = 0;
        int n = 0;
        for (const auto& b : bodies_)
            if (b->getInvMass() > 0) {
                speed += b->getLinearVelocity().length();
                height += b->getCenterOfMassPosition().y();
                ++n;
            }
        return {speed / n, height / n};
    }

private:
    void addStatic(std::unique_ptr<btCollisionShape> shape, const btTransform& pose) {
        add(std::move(shape), 0, btVector3(0, 0, 0), pose);
    }
    void addChair(Kind kind, const Body& body, const btTransform& pose, double margin) {
        std::unique_ptr<btCollisionShape> shape;
        if (kind == Kind::Group) {
            shape = std::make_unique<shatter::GroupShape>(body.primitives, margin);
        } else {
            auto compound = std::make_unique<btCompoundShape>();
            for (const auto& p : body.primitives) {
                auto hull = std::make_unique<btConvexHullShape>();
                for (const auto& v : p.vertices()) hull->addPoint(shatter::toBullet(v), false);
                hull->setMargin(btScalar(margin));
                hull->recalcLocalAabb();
                hull->initializePolyhedralFeatures(); // same clipping contacts as the group's children
                compound->addChildShape(btTransform::getIdentity(), hull.get());
                children_.push_back(std::move(hull));
            }
            shape = std::move(compound);
        }
        add(std::move(shape), body.mass, body.inertia, pose);
    }
    void add(std::unique_ptr<btCollisionShape> shape, double mass, const btVector3& inertia, const btTransform& pose) {
        auto motion = std::make_unique<btDefaultMotionState>(pose);
        btRigidBody::btRigidBodyConstructionInfo info(btScalar(mass), motion.get(), shape.get(), inertia);
        info.m_friction = 0.6f;
        auto body = std::make_unique<btRigidBody>(info);
        world_.addRigidBody(body.get());
        shapes_.push_back(std::move(shape));
        motions_.push_back(std::move(motion));
        bodies_.push_back(std::move(body));
    }

    btDefaultCollisionConfiguration config_;
    btCollisionDispatcher dispatcher_{&config_};
    btDbvtBroadphase broadphase_;
    btSequentialImpulseConstraintSolver solver_;
    btDiscreteDynamicsWorld world_{&dispatcher_, &broadphase_, &solver_, &config_};
    std::vector<std::unique_ptr<btCollisionShape>> children_;
    std::vector<std::unique_ptr<btCollisionShape>> shapes_;
    std::vector<std::unique_ptr<btMotionState>> motions_;
    std::vector<std::unique_ptr<btRigidBody>> bodies_;
};

struct Run {
    double msPerStep;
    double meanSpeed, meanHeight;
};

Run runOnce(Kind kind, const Options& o, const std::string& label, bool progress) {
    Scene scene(kind, o);
    const auto start = std::chrono::steady_clock::now();
    for (int s = 0; s < o.steps; ++s) {
        scene.step();
        if (progress && (s % 20 == 0 || s + 1 == o.steps))
            std::fprintf(stderr, "\r%s: step %d/%d   ", label.c_str(), s + 1, o.steps);
    }
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    if (progress) std::fprintf(stderr, "\r%*s\r", 60, "");
    const auto [speed, height] = scene.state();
    return {ms / o.steps, speed, height};
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    const size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

std::string jsonArray(const std::vector<double>& v) {
    std::ostringstream s;
    s << "[";
    for (size_t i = 0; i < v.size(); ++i) s << (i ? ", " : "") << v[i];
    return s.str() + "]";
}

} // namespace

int main(int argc, char** argv) {
    Options o;
    CLI::App app("Group shape vs Bullet's compound of convex hulls: a pile of chairs in a pit.\n"
                 "Each step is one fixed Bullet step of 1/240 s.",
                 "shatter-bench-groupshape");
    app.add_option("--bodies", o.bodies, "chairs in the pile")->check(CLI::Range(1, 100000));
    app.add_option("--steps", o.steps, "steps of 1/240 s per run")->check(CLI::Range(1, 1000000));
    app.add_option("--repeats", o.repeats, "runs of each shape (alternating)")->check(CLI::Range(1, 1000));
    app.add_option("--primitives-per-body", o.primitivesPerBody, "boxes per chair")->check(CLI::Range(1, 64));
    app.add_option("--margin", o.margin, "collision margin (m)")->check(CLI::Range(0.0, 0.1));
    app.add_option("--json", o.json, "also write the JSON result to this file");
    app.add_option("--only", o.only, "run only one side, for profiling (no ratio)")
        ->check(CLI::IsMember({"group", "compound"}));
    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        std::cerr << "shatter-bench-groupshape: " << e.what() << "\n" << "Run with --help for the options.\n";
        return 2;
    }

    const bool progress = isatty(fileno(stderr));
    std::printf("%d chairs of %d boxes, %d steps of 1/240 s, %d repeats, margin %g m\n", o.bodies,
                o.primitivesPerBody, o.steps, o.repeats, o.margin);
    std::vector<double> group, compound;
    for (int r = 0; r < o.repeats; ++r) {
        // Alternate which goes first, so warm caches and clocks favour neither.
        for (int k = 0; k < 2; ++k) {
            const Kind kind = (r + k) % 2 ? Kind::Compound : Kind::Group;
            const std::string name = kind == Kind::Group ? "group" : "compound";
            if (!o.only.empty() && o.only != name) continue;
            const Run run = runOnce(kind, o, name + " run " + std::to_string(r + 1), progress);
            (kind == Kind::Group ? group : compound).push_back(run.msPerStep);
            std::printf("run %d %-8s %8.3f ms/step  (end: mean speed %.3f m/s, mean height %.3f m)\n", r + 1,
                        name.c_str(), run.msPerStep, run.meanSpeed, run.meanHeight);
            std::fflush(stdout);
        }
    }
    if (!o.only.empty()) return 0;
    const double g = median(group), c = median(compound);
    std::printf("median ms/step: group %.3f, compound %.3f, ratio compound/group %.2f\n", g, c, c / g);

    std::ostringstream json;
    json << "{\"bodies\": " << o.bodies << ", \"steps\": " << o.steps << ", \"repeats\": " << o.repeats
         << ", \"primitives_per_body\": " << o.primitivesPerBody << ", \"margin\": " << o.margin
         << ", \"group_ms_per_step\": " << jsonArray(group) << ", \"compound_ms_per_step\": " << jsonArray(compound)
         << ", \"group_median_ms_per_step\": " << g << ", \"compound_median_ms_per_step\": " << c
         << ", \"ratio_compound_over_group\": " << c / g << "}";
    std::printf("%s\n", json.str().c_str());
    if (!o.json.empty()) {
        std::ofstream out(o.json);
        out << json.str() << "\n";
        if (!out) {
            std::cerr << "shatter-bench-groupshape: cannot write " << o.json << "\n";
            return 1;
        }
    }
    return 0;
}
