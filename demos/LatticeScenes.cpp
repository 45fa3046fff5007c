#include "demos/LatticeScenes.h"

#include <shatter/bullet_ext/Plugin.h>
#include <shatter/plugin/common/InputError.h>
#include <shatter/plugin/common/SettingCheck.h>
#include <shatter/plugin/lattice/AnchorRegion.h>
#include <shatter/plugin/lattice/TetGenReader.h>
#include <shatter/plugin/lattice/TetGenerators.h>

#include <BulletCollision/CollisionShapes/btBoxShape.h>
#include <BulletCollision/CollisionShapes/btSphereShape.h>

#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>

namespace shatter::demo {

void addDebrisOptions(CLI::App& cli, LatticeOptions& o) {
    cli.add_option("--debris-size", o.debrisSize,
                   "loose pieces at most this size in m (diameter about their centre of mass) are debris: they do not "
                   "collide with each other and rest sooner")
        ->capture_default_str();
    cli.add_option("--debris-budget", o.debrisBudget, "most live debris pieces per body, the oldest removed first (0: no limit)")
        ->capture_default_str();
    cli.add_option("--debris-lifetime", o.debrisLifetime, "s a debris piece lives (0: for ever)")->capture_default_str();
    cli.add_option("--debris-rest", o.debrisRest, "s a debris piece touching something stays put before it rests")
        ->capture_default_str();
    cli.add_flag("!--no-debris", o.debris, "no debris: every loose piece collides with every other");
    cli.add_option("--min-fragment-size", o.minFragmentSize,
                   "smallest loose piece in m (diameter about its centre of mass): smaller parts are merged with their "
                   "neighbours (0: single tets come loose)")
        ->capture_default_str();
}

void addFragmentBudgetOption(CLI::App& cli, LatticeOptions& o) {
    cli.add_option("--fragment-budget", o.fragmentBudget,
                   "most new fragment bodies per body and internal step; the other parts wait in the piece they came "
                   "from (0: no limit)")
        ->capture_default_str();
}

void addKeepPairsOption(CLI::App& cli, LatticeOptions& o) {
    cli.add_flag("--keep-pairs", o.keepPairs,
                 "a piece that loses parts stays in the world and keeps its contact pairs and manifolds instead of "
                 "making them anew (LatticeSettings::keepPairsOnShrink)");
}

namespace {

void addBallOptions(CLI::App& cli, Ball& ball, const std::string& note = "") {
    const std::string tail = note.empty() ? "" : " " + note;
    cli.add_option("--ball-speed", ball.speed, "ball speed in m/s, at most 10000" + tail)->capture_default_str();
    cli.add_option("--ball-mass", ball.mass, "ball mass in kg" + tail)->capture_default_str();
    cli.add_option("--ball-radius", ball.radius, "ball radius in m" + tail)->capture_default_str();
}

// Above 10 km/s (hypervelocity impact, beyond what rigid bodies and links model) a ball
// crosses tens of metres per step, and at 1e30 m/s Bullet's single-precision squares overflow:
// the ball stood still and the run ended with exit 0.
constexpr double kMaxBallSpeed = 1e4;

void checkBall(const Ball& ball) {
    if (!(std::isfinite(ball.speed) && ball.speed >= 0)) throw InputError("--ball-speed must be finite and >= 0 m/s");
    if (ball.speed > kMaxBallSpeed) {
        char text[96];
        std::snprintf(text, sizeof text, "--ball-speed must be at most %g m/s, got %g", kMaxBallSpeed, ball.speed);
        throw InputError(text);
    }
    if (!(std::isfinite(ball.mass) && ball.mass > 0)) throw InputError("--ball-mass must be finite and > 0 kg");
    if (!(std::isfinite(ball.radius) && ball.radius > 0)) throw InputError("--ball-radius must be finite and > 0 m");
}

// --tets, --material, --strength, --density, --jitter, --no-spreading, --no-replay, --no-freeze, the debris options.
void addLatticeOptions(CLI::App& cli, LatticeOptions& o, const std::string& body, bool jitter) {
    cli.add_option("--tets", o.tets, "TetGen mesh (PATH.ele with PATH.node) to use as the " + body);
    cli.add_option("--material", o.material, "adobe, brick, concrete, glass or ceramic")->capture_default_str();
    cli.add_option_function<double>(
        "--strength", [&o](double v) { o.strength = v, o.strengthGiven = true; },
        "link strength per m^2 of shared face in Pa (default: the material's)");
    cli.add_option_function<double>(
        "--density", [&o](double v) { o.density = v, o.densityGiven = true; },
        "density in kg/m^3 (default: the material's)");
    if (jitter)
        cli.add_option("--jitter", o.jitter, "node jitter of the built-in mesh, fraction of a cell in [0, 0.2]")
            ->capture_default_str();
    cli.add_flag("!--no-spreading", o.spreading, "turn off dynamic weakening around breaks");
    cli.add_flag("!--no-replay", o.replay,
                 "keep the impulses of a breaking body's contacts instead of solving them again against the fragments");
    cli.add_flag("!--no-freeze", o.freeze, "let resting fragments only sleep (Bullet's islands) instead of freezing them");
    addDebrisOptions(cli, o);
    addFragmentBudgetOption(cli, o);
    addKeepPairsOption(cli, o);
    cli.add_option("--sliver-quality", o.sliverQuality,
                   "tets of quality 6*sqrt(2)*V/Lmax^3 below this are bound to their best neighbour and never break off "
                   "alone (0 = none)")
        ->capture_default_str();
}

// The lattice settings every scene shares, from its options.
LatticeSettings latticeSettings(const std::string& name, const LatticeOptions& o, std::uint64_t seed) {
    LatticeSettings s;
    s.name = name;
    s.material = lattice::materialNamed(o.material);
    // Bad values (zero, negative, not finite) are reported by the body, naming it.
    if (o.strengthGiven) s.material.strength = o.strength;
    if (o.densityGiven) s.material.density = o.density;
    s.seed = seed;
    s.analysis.spreading.enabled = o.spreading;
    s.replayImpacts = o.replay;
    s.rest.freezeAtRest = o.freeze;
    s.sliverQuality = o.sliverQuality;
    s.minFragmentSize = o.minFragmentSize;
    s.fragmentBudget = o.fragmentBudget;
    s.keepPairsOnShrink = o.keepPairs;
    if (o.debris) {
        s.debris.maxSize = o.debrisSize;
        s.debris.budget = o.debrisBudget;
        s.debris.lifetime = o.debrisLifetime;
        s.debris.sleepAfter = o.debrisRest;
    }
    return s;
}

lattice::TetMesh readOr(const LatticeOptions& o, const std::string& program, lattice::TetMesh (*builtIn)(const LatticeOptions&, std::uint64_t),
                        std::uint64_t seed) {
    lattice::TetMesh mesh = o.tets.empty() ? builtIn(o, seed) : lattice::readTetGen(o.tets);
    for (const auto& w : mesh.warnings) std::cerr << program << ": warning: " << w << "\n";
    return mesh;
}

// The sliver count on stderr (summary.json has it too): a mesh that has some is worth knowing.
LatticeBody& reportSlivers(LatticeBody& body, const std::string& program) {
    if (body.sliverCount() > 0)
        std::cerr << program << ": body '" << body.name() << "': " << body.sliverCount() << " sliver tets (quality below "
                  << body.settings().sliverQuality << ") bound to their best neighbours by " << body.boundLinkCount()
                  << " unbreakable links\n";
    return body;
}

struct Bounds {
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(INFINITY), hi = Eigen::Vector3d::Constant(-INFINITY);
};
Bounds boundsOf(const lattice::TetMesh& mesh) {
    Bounds b;
    for (const auto& n : mesh.nodes) b.lo = b.lo.cwiseMin(n), b.hi = b.hi.cwiseMax(n);
    return b;
}

// A ball at `at` flying along the unit `direction` at the ball's speed.
btRigidBody& launchBall(Scene& scene, const Ball& ball, const btVector3& at, const btVector3& direction,
                        const std::string& name = "ball") {
    btRigidBody& body = scene.addRigidBody(std::make_unique<btSphereShape>(btScalar(ball.radius)), ball.mass,
                                           btTransform(btQuaternion::getIdentity(), at), name);
    body.setLinearVelocity(direction * btScalar(ball.speed));
    return body;
}

void addSummaries(Scene& scene, const nlohmann::json& counts) {
    for (const auto& [key, value] : counts.items()) scene.addSummary(key, value);
}

// The wall: 17 × 10 × 4 cells of 10 cm, six tets each: 4,080 tets, as in the source.
lattice::TetMesh builtInWall(const LatticeOptions& o, std::uint64_t seed) {
    lattice::GeneratorOptions g;
    g.name = "wall";
    g.jitter = o.jitter;
    g.seed = seed;
    return lattice::tetBox({1.7, 1.0, 0.4}, {17, 10, 4}, g);
}

// The table top: 1.2 × 0.7 m, 2 cm thick, in 4 cm cells: 3,150 tets.
lattice::TetMesh builtInTop(const LatticeOptions& o, std::uint64_t seed) {
    lattice::GeneratorOptions g;
    g.name = "top";
    g.jitter = o.jitter;
    g.seed = seed;
    return lattice::tetSlab(1.2, 0.7, 0.02, 0.04, 1, g);
}

// The noise walls: 12 × 8 × 2 cells of 8 cm, 1,152 tets each (no jitter: the uniform wall is
// truly regular).
lattice::TetMesh builtInNoiseWall(const LatticeOptions&, std::uint64_t) {
    lattice::GeneratorOptions g;
    g.name = "wall";
    return lattice::tetBox({0.96, 0.64, 0.16}, {12, 8, 2}, g);
}

constexpr double kLegHeight = 0.72;

// "x0,y0,..." as exactly `count` finite numbers, or nothing.
std::vector<double> numbersIn(const std::string& text, size_t count) {
    std::vector<double> out;
    std::istringstream in(text);
    std::string item;
    while (std::getline(in, item, ',')) {
        size_t used = 0;
        double v = 0;
        try {
            v = std::stod(item, &used);
        } catch (const std::exception&) {
            return {};
        }
        if (used != item.size() || !std::isfinite(v)) return {};
        out.push_back(v);
    }
    return out.size() == count ? out : std::vector<double>{};
}

void addAnchorOption(CLI::App& cli, LatticeOptions& o) {
    cli.add_option("--anchor", o.anchor,
                   "fixed tets: bottom (a face on the lowest plane), none, tets:I,J,... (0-based), below:H (centroid y <= H) "
                   "or box:x0,y0,z0,x1,y1,z1 (centroid inside) in mesh coordinates, world-below:H or world-box:... in "
                   "world coordinates, contact or contact:D (within D m, default 0.005, of the ground or legs)")
        ->capture_default_str();
}

const char* const kAnchorForms =
    "--anchor must be bottom, none, tets:I,J,..., below:H, box:x0,y0,z0,x1,y1,z1 (x0 <= x1, ...), world-below:H, "
    "world-box:... or contact[:D] (D > 0 m)";

// "below:H" or "box:x0,y0,z0,x1,y1,z1" as a region (mesh coordinates), or nothing.
std::optional<lattice::AnchorRegion> regionIn(const std::string& text) {
    const auto colon = text.find(':');
    const std::string kind = text.substr(0, colon), rest = colon == std::string::npos ? "" : text.substr(colon + 1);
    if (kind == "below") {
        if (const auto h = numbersIn(rest, 1); !h.empty()) return lattice::AnchorRegion::below(h[0]);
    } else if (kind == "box") {
        if (const auto c = numbersIn(rest, 6); !c.empty()) {
            const Eigen::Vector3d lo(c[0], c[1], c[2]), hi(c[3], c[4], c[5]);
            if ((lo.array() <= hi.array()).all()) return lattice::AnchorRegion::box(lo, hi);
        }
    }
    return std::nullopt;
}

// "I,J,..." as tet indices (whole numbers >= 0), or nothing.
std::vector<int> indicesIn(const std::string& text) {
    std::vector<int> out;
    std::istringstream in(text);
    std::string item;
    while (std::getline(in, item, ',')) {
        size_t used = 0;
        long v = -1;
        try {
            v = std::stol(item, &used);
        } catch (const std::exception&) {
            return {};
        }
        if (used != item.size() || v < 0 || v > INT32_MAX) return {};
        out.push_back(int(v));
    }
    return out;
}

} // namespace

std::vector<int> anchorTets(const std::string& anchor, const lattice::TetMesh& mesh, const std::string& body) {
    if (anchor == "none") return {};
    if (anchor == "bottom") {
        const std::vector<int> tets = lattice::tetsWithFaceOnPlane(mesh, {0, 1, 0}, boundsOf(mesh).lo.y(), 1e-6);
        if (tets.empty())
            throw InputError("body '" + body + "': the mesh has no face on its lowest plane to anchor it by (try --anchor below:H or contact)");
        return tets;
    }
    if (anchor.rfind("tets:", 0) == 0) {
        if (std::vector<int> tets = indicesIn(anchor.substr(5)); !tets.empty()) return tets; // checked against the mesh by the body
    } else if (const auto region = regionIn(anchor)) {
        return lattice::anchoredTets(mesh, *region, body);
    }
    throw InputError(std::string(kAnchorForms) + ", got '" + anchor + "'");
}

void setAnchor(const std::string& anchor, const lattice::TetMesh& mesh, LatticeSettings& settings,
               const std::vector<const btCollisionObject*>& supports) {
    if (anchor == "contact" || anchor.rfind("contact:", 0) == 0) {
        const auto d = anchor == "contact" ? std::vector<double>{0.005} : numbersIn(anchor.substr(8), 1);
        if (d.empty() || !(d[0] > 0)) throw InputError(std::string(kAnchorForms) + ", got '" + anchor + "'");
        settings.anchorTo = supports;
        settings.anchorDistance = d[0];
    } else if (anchor.rfind("world-", 0) == 0) {
        const auto region = regionIn(anchor.substr(6));
        if (!region) throw InputError(std::string(kAnchorForms) + ", got '" + anchor + "'");
        settings.anchorRegions.push_back(region->inWorld());
    } else {
        settings.fixedTets = anchorTets(anchor, mesh, settings.name);
    }
}

namespace {

// Pieces that are one tet of quality below lattice::kSliverQuality (none while slivers are bound).
int loneSlivers(const LatticeBody& b) {
    const lattice::TetMesh& mesh = b.lattice().mesh();
    int n = 0;
    for (const auto& p : b.pieces())
        n += p.lattice.particles.size() == 1 && lattice::tetQuality(mesh, mesh.tets[p.lattice.particles[0]]) < lattice::kSliverQuality;
    return n;
}

} // namespace

nlohmann::json latticeCounts(const LatticeBody& b) {
    return {{"tets", b.tetCount()},
            {"links", b.linkCount()},
            {"links_broken", b.brokenLinkCount()},
            {"fragments", b.pieceCount()},
            {"fragments_frozen", b.frozenPieceCount()},
            {"mass_initial", b.initialMass()},
            {"mass_final", b.currentMass()},
            {"mass_removed_debris", b.removedDebrisMass()},
            {"debris_removed", b.removedDebrisCount()},
            {"mass_relative_change", (b.currentMass() + b.removedDebrisMass() - b.initialMass()) / b.initialMass()},
            {"slivers", b.sliverCount()},
            {"fragments_lone_sliver", loneSlivers(b)}};
}

double sceneEnergy(Scene& scene, const std::vector<LatticeBody*>& bodies) {
    const btVector3 gravity = scene.world().getGravity();
    double e = 0.0;
    for (const LatticeBody* b : bodies) e += b->mechanicalEnergy(gravity);
    for (const auto& entry : scene.rigidBodies()) {
        const btRigidBody& r = *entry->body;
        if (r.getInvMass() > 0) e += kineticEnergy(r) - double(gravity.dot(r.getCenterOfMassPosition())) / double(r.getInvMass());
    }
    return e;
}

void trackMotion(Scene& scene, std::vector<LatticeBody*> bodies) {
    struct Record {
        double energyInitial, energyMax;
        LatticeBody::Speeds fastest;
        double pointMax = 0.0;
        int speedFrame = 0, energyFrame = 0;
    };
    const double start = sceneEnergy(scene, bodies);
    auto record = std::make_shared<Record>(Record{start, start, {}});
    scene.onFrame([&scene, bodies, record](const Frame& frame) {
        const double e = sceneEnergy(scene, bodies);
        if (e > record->energyMax) record->energyMax = e, record->energyFrame = frame.index;
        for (const LatticeBody* b : bodies) {
            const LatticeBody::Speeds v = b->fastestPieces();
            if (v.centre > record->fastest.centre) record->fastest = v, record->speedFrame = frame.index;
            record->pointMax = std::max(record->pointMax, v.point);
        }
        if (frame.index != frame.count) return;
        scene.addSummary("fragment_speed_max", record->fastest.centre);
        scene.addSummary("fragment_speed_max_frame", record->speedFrame);
        scene.addSummary("fragment_speed_max_tets", record->fastest.tets);
        scene.addSummary("fragment_point_speed_max", record->pointMax);
        scene.addSummary("energy_initial", record->energyInitial);
        scene.addSummary("energy_max", record->energyMax);
        scene.addSummary("energy_max_frame", record->energyFrame);
        scene.addSummary("energy_final", e);
    });
}

void addOptions(CLI::App& cli, WallOptions& o) {
    addBallOptions(cli, o.ball);
    addLatticeOptions(cli, o.lattice, "wall", true);
    addAnchorOption(cli, o.lattice);
}

void addOptions(CLI::App& cli, TableOptions& o) {
    addBallOptions(cli, o.ball, "(dropped from 0.4 m above the top)");
    addLatticeOptions(cli, o.lattice, "table top (mesh units m, y up)", true);
    addAnchorOption(cli, o.lattice);
    cli.add_option("--cleaving", o.cleaving, "strength factor of the links on the plane x = 0 (1 = no cleaving plane)")
        ->capture_default_str();
    cli.add_option("--cleaving-band", o.cleavingBand,
                   "half-width in m of the cleaving band: faces whose centre is this close to the plane x = 0 are weakened")
        ->capture_default_str();
    cli.add_flag("!--no-crack-run", o.crackRuns,
                 "a crack on the cleaving plane stops where the loads stop it instead of running along the plane");
}

void addOptions(CLI::App& cli, NoiseOptions& o) {
    addBallOptions(cli, o.ball, "(both balls)");
    addLatticeOptions(cli, o.lattice, "both walls", false);
    cli.add_option("--noise-amplitude", o.amplitude, "strength × (1 + amplitude · noise) on the noisy wall")
        ->capture_default_str();
    cli.add_option("--noise-scale", o.scale, "size of the noise features in m")->capture_default_str();
}

std::vector<LatticeBody*> buildScene(Scene& scene, const WallOptions& o, const std::string& program) {
    checkBall(o.ball);
    scene.useSplitImpulsesOnly();
    const btRigidBody& ground = scene.addGround();
    const lattice::TetMesh mesh = readOr(o.lattice, program, builtInWall, scene.seed());
    LatticeSettings settings = latticeSettings("wall", o.lattice, scene.seed());
    // Standing on the ground: the lowest node at y = 0, anchored as --anchor says.
    const Bounds b = boundsOf(mesh);
    setAnchor(o.lattice.anchor, mesh, settings, {&ground});
    const btTransform pose(btQuaternion::getIdentity(), btVector3(0, btScalar(-b.lo.y()), 0));
    LatticeBody& wall = reportSlivers(scene.plugin().addLatticeBody(mesh, settings, pose), program);
    // The ball flies at the wall's face, a little below the middle of its height.
    const btVector3 ballAt(0, btScalar(0.45 * (b.hi.y() - b.lo.y())), btScalar(b.hi.z() + o.ball.radius + 0.3));
    launchBall(scene, o.ball, ballAt, btVector3(0, 0, -1)).setFriction(0.5);
    scene.onFrame([&scene, &wall](const Frame& frame) {
        if (frame.index == frame.count) addSummaries(scene, latticeCounts(wall));
    });
    trackMotion(scene, {&wall});
    return {&wall};
}

std::vector<LatticeBody*> buildScene(Scene& scene, const TableOptions& o, const std::string& program) {
    checkBall(o.ball);
    if (!(std::isfinite(o.cleaving) && o.cleaving > 0)) throw InputError("--cleaving must be finite and > 0");
    scene.useSplitImpulsesOnly();
    scene.addGround();
    const lattice::TetMesh mesh = readOr(o.lattice, program, builtInTop, scene.seed());
    const Bounds b = boundsOf(mesh);
    const Eigen::Vector3d centre = 0.5 * (b.lo + b.hi), size = b.hi - b.lo;
    // Four legs under the corners, the top resting on them.
    const double leg = 0.03;
    std::vector<const btCollisionObject*> legs;
    for (int sx : {-1, 1})
        for (int sz : {-1, 1}) {
            const btVector3 at(btScalar(centre.x() + sx * (0.5 * size.x() - 2 * leg)), btScalar(0.5 * kLegHeight),
                               btScalar(centre.z() + sz * (0.5 * size.z() - 2 * leg)));
            legs.push_back(&scene.addRigidBody(
                std::make_unique<btBoxShape>(btVector3(btScalar(leg), btScalar(0.5 * kLegHeight), btScalar(leg))), 0.0,
                btTransform(btQuaternion::getIdentity(), at), "leg"));
        }
    LatticeSettings settings = latticeSettings("top", o.lattice, scene.seed());
    requirePositive(settings.name, "cleaving band (--cleaving-band, m)", o.cleavingBand);
    setAnchor(o.lattice.anchor, mesh, settings, legs);
    if (o.cleaving != 1.0) {
        lattice::CleavingPlane plane;
        plane.point = centre;
        plane.normal = Eigen::Vector3d::UnitX();
        plane.distance = o.cleavingBand; // metres, not relative to the mesh: a tall mesh once had 16,022 links in it
        plane.factor = o.cleaving;
        plane.crackRuns = o.crackRuns;
        settings.cleavingPlanes.push_back(plane);
    }
    const btTransform pose(btQuaternion::getIdentity(), btVector3(0, btScalar(kLegHeight - b.lo.y() + 0.001), 0));
    LatticeBody& top = reportSlivers(scene.plugin().addLatticeBody(mesh, settings, pose), program);
    // The ball falls on the top a little off the plane, so the crack has to find it.
    const btVector3 ballAt(btScalar(centre.x() + 0.06), btScalar(kLegHeight + size.y() + 0.4), btScalar(centre.z() + 0.05));
    launchBall(scene, o.ball, ballAt, btVector3(0, -1, 0));
    scene.onFrame([&scene, &top](const Frame& frame) {
        if (frame.index != frame.count) return;
        addSummaries(scene, latticeCounts(top));
        int onPlane = 0;
        for (const auto& l : top.lattice().links()) {
            if (!l.broken) continue;
            for (const auto& p : top.settings().cleavingPlanes) onPlane += lattice::faceNearPlane(top.lattice(), l, p);
        }
        scene.addSummary("links_broken_on_cleaving_plane", onPlane);
    });
    trackMotion(scene, {&top});
    return {&top};
}

std::vector<LatticeBody*> buildScene(Scene& scene, const NoiseOptions& o, const std::string& program) {
    checkBall(o.ball);
    scene.useSplitImpulsesOnly();
    scene.addGround();
    const lattice::TetMesh mesh = readOr(o.lattice, program, builtInNoiseWall, scene.seed());
    const Bounds b = boundsOf(mesh);
    const double width = b.hi.x() - b.lo.x();
    // Two walls side by side take the same hit: uniform strengths on the left, seeded noise
    // and dynamic weakening on the right.
    auto addWall = [&](bool noisy, double x) -> LatticeBody& {
        LatticeSettings s = latticeSettings(noisy ? "noisy" : "uniform", o.lattice, scene.seed());
        s.fixedTets = lattice::tetsWithFaceOnPlane(mesh, {0, 1, 0}, b.lo.y(), 1e-6);
        s.analysis.spreading.enabled = noisy && o.lattice.spreading;
        s.noise.enabled = noisy;
        s.noise.amplitude = o.amplitude;
        s.noise.scale = o.scale;
        const btTransform pose(btQuaternion::getIdentity(), btVector3(btScalar(x), btScalar(-b.lo.y()), 0));
        LatticeBody& body = reportSlivers(scene.plugin().addLatticeBody(mesh, s, pose), program);
        const btVector3 at(btScalar(x), btScalar(0.5 * (b.hi.y() - b.lo.y())), btScalar(b.hi.z() + o.ball.radius + 0.2));
        launchBall(scene, o.ball, at, btVector3(0, 0, -1), noisy ? "ball_noisy" : "ball_uniform");
        return body;
    };
    LatticeBody& uniform = addWall(false, -0.75 * width);
    LatticeBody& noisy = addWall(true, 0.75 * width);
    scene.onFrame([&scene, &uniform, &noisy](const Frame& frame) {
        if (frame.index != frame.count) return;
        const auto a = latticeCounts(uniform), c = latticeCounts(noisy);
        for (const char* key : {"tets", "links", "links_broken", "fragments"})
            scene.addSummary(key, a[key].get<int>() + c[key].get<int>());
        for (const char* key : {"mass_initial", "mass_final"}) scene.addSummary(key, a[key].get<double>() + c[key].get<double>());
        const double before = a["mass_initial"].get<double>() + c["mass_initial"].get<double>();
        const double after = a["mass_final"].get<double>() + c["mass_final"].get<double>();
        scene.addSummary("mass_relative_change", (after - before) / before);
        scene.addSummary("uniform", a);
        scene.addSummary("noisy", c);
    });
    trackMotion(scene, {&uniform, &noisy});
    return {&uniform, &noisy};
}

} // namespace shatter::demo
