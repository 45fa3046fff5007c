#pragma once
// What the world's floating-point precision lets Bullet simulate, and warnings for bodies
// outside it. Bullet is built in single precision by default (bullet.pc); the bounds follow
// its SIMD_EPSILON, so a double-precision build gets its own.
#include <Eigen/Core>

#include <BulletCollision/BroadphaseCollision/btDispatcher.h>
#include <LinearMath/btScalar.h>

#include <functional>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

namespace shatter {

// Heaviest body Bullet's contact solver still moves when it touches a static body (kg):
// btSequentialImpulseConstraintSolver::convertContact skips a contact when both bodies'
// inverse-mass vectors (1/m times the linear factor (1, 1, 1)) are fuzzyZero, that is
// 3/m² < SIMD_EPSILON², so a body with m > √3/SIMD_EPSILON gets no contact response and falls
// through the ground. 1.45e7 kg in single precision (a 2.4 m cube of steel).
double heaviestMovableMass();

// Sizes between which contacts behave (m): below, the world's contact breaking threshold
// (gContactBreakingThreshold, 2 cm) and the default collision margins are as large as the
// body; above, a float keeps only ~0.1 mm of a coordinate and contact points jitter.
constexpr double smallestSafeSize = 0.01;
constexpr double largestSafeSize = 1000.0;
// Mass ratio of two dynamic bodies in contact above which the sequential-impulse solver
// converges too slowly (the light body sinks into or jitters on the heavy one).
constexpr double largestSafeMassRatio = 1000.0;

// Warnings naming the body, the figure and the remedy, for a body of `mass` kg (0: static)
// whose bounding box has sides `extent` (m).
std::vector<std::string> precisionWarnings(const std::string& body, double mass, const Eigen::Vector3d& extent);

// Finds dynamic pairs in contact whose masses differ by more than largestSafeMassRatio; warns
// once per pair. `name` returns the name of a body the application gave Shatter, an empty
// string for an object that is not Shatter's, and nothing for a piece Shatter made itself
// (a lattice fragment): pieces are as light as the breaking made them, a warning could not
// be acted on. Pairs of two application objects are the application's business.
class MassRatioWatch {
public:
    using Namer = std::function<std::optional<std::string>(const btCollisionObject&)>;
    void check(btDispatcher& dispatcher, const Namer& name, std::vector<std::string>& warnings);
    void forget(const btCollisionObject& object);

private:
    std::set<std::pair<const btCollisionObject*, const btCollisionObject*>> warned_;
};

} // namespace shatter
