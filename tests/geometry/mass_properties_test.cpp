// Mass properties against closed forms: box and triangular prism.
#include <shatter/plugin/geometry/ConvexPolyhedron.h>
#include <shatter/plugin/geometry/MassProperties.h>
#include <shatter/plugin/geometry/FaceList.h>
#include "tests/support/SameBits.h"
#include "tests/support/SamePolyhedron.h"

#include <algorithm>
#include <cstring>
#include <memory>
#include <stdexcept>

#include <gtest/gtest.h>

using namespace shatter::geometry;

namespace {

ConvexPolyhedron box(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
    std::vector<Eigen::Vector3d> v;
    for (int i = 0; i < 8; ++i)
        v.emplace_back(i & 1 ? hi.x() : lo.x(), i & 2 ? hi.y() : lo.y(), i & 4 ? hi.z() : lo.z());
    std::vector<std::vector<int>> f = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    return ConvexPolyhedron::create(v, f, {0, 1, 2, 3, 4, 5, 6, 7}, "box");
}

// Every bit of two Eigen objects or std::vectors of plain values equal (== takes -0 for +0).
template <class T>
bool sameBytes(const T& a, const T& b) {
    return a.size() == b.size() && std::memcmp(a.data(), b.data(), size_t(a.size()) * sizeof(*a.data())) == 0;
}

} // namespace

TEST(MassProperties, BoxMatchesClosedForm) {
    const double a = 2.0, b = 0.5, c = 0.25, rho = 700.0;
    const ConvexPolyhedron p = box({1, 2, 3}, {1 + a, 2 + b, 3 + c});
    const MassProperties m = p.massProperties(rho);
    const double mass = rho * a * b * c;
    EXPECT_NEAR(m.volume, a * b * c, 1e-12);
    EXPECT_NEAR(m.mass, mass, 1e-9);
    EXPECT_TRUE(m.centerOfMass.isApprox(Eigen::Vector3d(1 + a / 2, 2 + b / 2, 3 + c / 2), 1e-12));
    Eigen::Matrix3d expected = Eigen::Vector3d(b * b + c * c, a * a + c * c, a * a + b * b).asDiagonal();
    expected *= mass / 12.0;
    EXPECT_LT((m.inertia - expected).norm(), 1e-9 * expected.norm());
}

TEST(MassProperties, RotatedBoxHasRotatedInertiaAndSamePrincipalMoments) {
    const ConvexPolyhedron p = box({-1, -0.5, -0.25}, {1, 0.5, 0.25});
    const Eigen::Isometry3d t = Eigen::Translation3d(3, -2, 5) * Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized());
    const MassProperties m0 = p.massProperties(1000.0);
    const MassProperties m1 = p.transformed(t).massProperties(1000.0);
    EXPECT_NEAR(m1.mass, m0.mass, 1e-9);
    EXPECT_TRUE(m1.centerOfMass.isApprox(t * m0.centerOfMass, 1e-12));
    const Eigen::Matrix3d r = t.linear();
    EXPECT_LT((m1.inertia - r * m0.inertia * r.transpose()).norm(), 1e-9 * m0.inertia.norm());
    EXPECT_TRUE(m1.principal().moments.isApprox(m0.principal().moments, 1e-9));
    EXPECT_NEAR(m1.principal().axes.determinant(), 1.0, 1e-12);
}

TEST(MassProperties, TriangularPrismMatchesClosedForm) {
    // Right-triangle legs a (x) and b (y), length L along z. Centroid (a/3, b/3, L/2).
    const double a = 0.6, b = 0.3, L = 2.0, rho = 2500.0;
    std::vector<Eigen::Vector3d> v = {{0, 0, 0}, {a, 0, 0}, {0, b, 0}, {0, 0, L}, {a, 0, L}, {0, b, L}};
    std::vector<std::vector<int>> f = {{0, 2, 1}, {3, 4, 5}, {0, 1, 4, 3}, {1, 2, 5, 4}, {2, 0, 3, 5}};
    const MassProperties m = ConvexPolyhedron::create(v, f, {0, 1, 2, 3, 4, 5}, "prism").massProperties(rho);
    const double mass = rho * 0.5 * a * b * L;
    EXPECT_NEAR(m.mass, mass, 1e-9);
    EXPECT_TRUE(m.centerOfMass.isApprox(Eigen::Vector3d(a / 3, b / 3, L / 2), 1e-12));
    // Right triangle about its centroid: Ixx_2d = m b²/18, Iyy_2d = m a²/18, Ixy = +m a b/36
    // (product of inertia enters the tensor with a minus sign: I_xy = -∫xy dm = m a b / 36).
    const double Ixx = mass * (b * b / 18.0 + L * L / 12.0);
    const double Iyy = mass * (a * a / 18.0 + L * L / 12.0);
    const double Izz = mass * (a * a + b * b) / 18.0;
    const double Ixy = mass * a * b / 36.0;
    EXPECT_NEAR(m.inertia(0, 0), Ixx, 1e-9 * Ixx);
    EXPECT_NEAR(m.inertia(1, 1), Iyy, 1e-9 * Iyy);
    EXPECT_NEAR(m.inertia(2, 2), Izz, 1e-9 * Izz);
    EXPECT_NEAR(m.inertia(0, 1), Ixy, 1e-9 * Izz);
    EXPECT_NEAR(m.inertia(0, 2), 0.0, 1e-9 * Izz);
}

TEST(MassProperties, SumUsesParallelAxisTheorem) {
    // Two unit cubes side by side equal one 2x1x1 box.
    MassProperties sum = box({0, 0, 0}, {1, 1, 1}).massProperties(1.0);
    sum += box({1, 0, 0}, {2, 1, 1}).massProperties(1.0);
    const MassProperties whole = box({0, 0, 0}, {2, 1, 1}).massProperties(1.0);
    EXPECT_NEAR(sum.mass, whole.mass, 1e-12);
    EXPECT_TRUE(sum.centerOfMass.isApprox(whole.centerOfMass, 1e-12));
    EXPECT_LT((sum.inertia - whole.inertia).norm(), 1e-12);
}

TEST(ConvexPolyhedron, RejectsOpenInvertedAndConcaveInput) {
    std::vector<Eigen::Vector3d> v = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    std::vector<int> ids = {0, 1, 2, 3};
    const std::vector<std::vector<int>> tet = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {2, 0, 3}};
    EXPECT_NO_THROW(ConvexPolyhedron::create(v, tet, ids));
    auto open = tet;
    open.pop_back();
    EXPECT_THROW(ConvexPolyhedron::create(v, open, ids, "t"), shatter::InputError); // only 3 faces
    auto flipped = tet;
    flipped.back() = {0, 2, 3}; // one face wound the wrong way
    EXPECT_THROW(ConvexPolyhedron::create(v, flipped, ids, "t"), shatter::InputError);
    std::vector<std::vector<int>> inverted;
    for (auto f : tet) inverted.push_back({f[0], f[2], f[1]});
    EXPECT_THROW(ConvexPolyhedron::create(v, inverted, ids, "t"), shatter::InputError);
    auto nan = v;
    nan[3].z() = std::nan("");
    EXPECT_THROW(ConvexPolyhedron::create(nan, tet, ids, "t"), shatter::InputError);
    try {
        ConvexPolyhedron::create(v, inverted, ids, "my tet");
    } catch (const shatter::InputError& e) {
        EXPECT_NE(std::string(e.what()).find("my tet"), std::string::npos);
    }
}

TEST(ConvexPolyhedron, SupportAndSignedDistance) {
    const ConvexPolyhedron p = box({0, 0, 0}, {1, 2, 3});
    EXPECT_TRUE(p.support({1, 1, 1}).isApprox(Eigen::Vector3d(1, 2, 3)));
    EXPECT_NEAR(p.signedDistance({0.5, 1, 1.5}), -0.5, 1e-12);
    EXPECT_NEAR(p.signedDistance({0.5, 1, 4}), 1.0, 1e-12);
}

// A fracture's id swaps write a carrier's new ids into its own storage: the ids change, the
// storage and the geometry do not, and a wrong count is refused with the polyhedron unchanged.
TEST(ConvexPolyhedron, OverwrittenIdsGoIntoTheSameStorage) {
    ConvexPolyhedron p = box({0, 0, 0}, {1, 2, 3});
    const ConvexPolyhedron before = p;
    const int* storage = p.globalIds().data();
    const std::vector<int> ids = {7, 6, 5, 4, 40, 41, 42, 43};
    p.overwriteGlobalIds(ids);
    EXPECT_EQ(p.globalIds(), ids);
    EXPECT_EQ(p.globalIds().data(), storage);
    EXPECT_TRUE(sameBytes(p.vertices(), before.vertices()));
    EXPECT_EQ(p.volume(), before.volume());
    const std::vector<int> tooFew = {1, 2, 3};
    EXPECT_THROW(p.overwriteGlobalIds(tooFew), std::invalid_argument);
    EXPECT_EQ(p.globalIds(), ids);
}

// A cut piece is made from its clipper's flat face list: a face of collinear vertices is left
// out, and the rest is the polyhedron createTrusted makes of the kept faces, bit for bit (a
// tilted, off-origin box, so that nothing is a round number, with a flat face along an edge).
TEST(ConvexPolyhedron, TrustedFromFlatFacesDropsCollinearFacesAndIsTheSamePolyhedron) {
    const Eigen::Isometry3d tilt = Eigen::Translation3d(0.3, -1.7, 2.1) *
                                   Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized());
    const ConvexPolyhedron b = box({0.1, 0.2, 0.3}, {0.7, 1.9, 0.8}).transformed(tilt);
    const std::span<const int> edgeFace = b.faces()[0];
    std::vector<Eigen::Vector3d> vertices = b.vertices();
    vertices.push_back(0.5 * (vertices[size_t(edgeFace[0])] + vertices[size_t(edgeFace[1])]));
    std::vector<int> ids = b.globalIds();
    ids.push_back(int(ids.size()));
    std::vector<int> faceStart{0}, faceVertices;
    for (const auto& face : b.faces()) {
        faceVertices.insert(faceVertices.end(), face.begin(), face.end());
        faceStart.push_back(int(faceVertices.size()));
        if (faceStart.size() == 3) { // the flat face second
            faceVertices.insert(faceVertices.end(), {edgeFace[0], int(vertices.size()) - 1, edgeFace[1]});
            faceStart.push_back(int(faceVertices.size()));
        }
    }
    const ConvexPolyhedron plain = ConvexPolyhedron::createTrusted(vertices, b.faces(), ids);
    const ConvexPolyhedron clipped =
        ConvexPolyhedron::createTrustedDroppingFlatFaces(vertices, faceStart, faceVertices, ids);
    shatter::test::expectSamePolyhedron(clipped, plain);
    EXPECT_EQ(clipped.globalIds(), ids);
    EXPECT_NEAR(plain.volume(), 0.6 * 1.7 * 0.5, 1e-12);
}

// withGlobalIds copies everything but the ids bit for bit, also a moved primitive's inertia
// turn not yet applied.
TEST(ConvexPolyhedron, WithGlobalIdsKeepsTheGeometryBitForBit) {
    const ConvexPolyhedron rest = box({-1, -0.5, -0.25}, {1, 0.5, 0.25});
    ConvexPolyhedron moved = rest;
    moved.moveTo(rest, Eigen::Translation3d(3, -2, 5) * Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()));
    std::vector<int> ids(moved.vertices().size());
    for (size_t i = 0; i < ids.size(); ++i) ids[i] = int(100 + i);
    const ConvexPolyhedron renamed = moved.withGlobalIds(ids);
    EXPECT_EQ(renamed.globalIds(), ids);
    EXPECT_EQ(renamed.vertices(), moved.vertices());
    EXPECT_EQ(renamed.faces(), moved.faces());
    ASSERT_EQ(renamed.planes().size(), moved.planes().size());
    for (size_t f = 0; f < moved.planes().size(); ++f) {
        EXPECT_EQ(renamed.planes()[f].normal, moved.planes()[f].normal);
        EXPECT_EQ(renamed.planes()[f].offset, moved.planes()[f].offset);
    }
    EXPECT_EQ(renamed.bounds().min, moved.bounds().min);
    EXPECT_EQ(renamed.bounds().max, moved.bounds().max);
    EXPECT_EQ(renamed.centerOfMass(), moved.centerOfMass());
    EXPECT_EQ(renamed.massProperties(2.0).inertia, moved.massProperties(2.0).inertia);
    EXPECT_THROW(moved.withGlobalIds({1, 2}), std::invalid_argument);
}

// moveTo turns the inertia only when it is read: the value is the eager turn's, bit for bit,
// also for a primitive moved from one that was itself moved (a turn not yet applied).
TEST(ConvexPolyhedron, MovedInertiaIsTheTurnedRestInertiaBitForBit) {
    const ConvexPolyhedron rest = box({-1, -0.5, -0.25}, {1, 0.5, 0.25});
    const Eigen::Isometry3d t1 = Eigen::Translation3d(3, -2, 5) * Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized());
    const Eigen::Isometry3d t2 = Eigen::Translation3d(-1, 0, 2) * Eigen::AngleAxisd(-1.1, Eigen::Vector3d(0, 1, 1).normalized());
    const Eigen::Matrix3d r1 = t1.linear(), r2 = t2.linear();
    const double rho = 700.0;
    ConvexPolyhedron once = rest;
    once.moveTo(rest, t1);
    const Eigen::Matrix3d inertia1 = r1 * rest.massProperties(1.0).inertia * r1.transpose();
    EXPECT_EQ(once.massProperties(rho).inertia, Eigen::Matrix3d(inertia1 * rho));
    ConvexPolyhedron twice = once;
    twice.moveTo(once, t2);
    const Eigen::Matrix3d inertia2 = r2 * inertia1 * r2.transpose();
    EXPECT_EQ(twice.massProperties(rho).inertia, Eigen::Matrix3d(inertia2 * rho));
    // And it is the moved solid's inertia.
    const MassProperties direct = rest.transformed(t2 * t1).massProperties(rho);
    EXPECT_LT((twice.massProperties(rho).inertia - direct.inertia).norm(), 1e-9 * direct.inertia.norm());
    // A polyhedron built again from points carries no pending turn.
    EXPECT_TRUE(twice.transformed(Eigen::Isometry3d::Identity()).massProperties(rho).inertia.isApprox(direct.inertia, 1e-12));
}

// moved(t) is a copy moved by moveTo, bit for bit (it writes the moved vertices and planes once
// instead of copying them first), also from a primitive whose own turn is still pending.
TEST(ConvexPolyhedron, MovedIsACopyMovedByMoveToBitForBit) {
    const ConvexPolyhedron rest = box({-1, -0.5, -0.25}, {1, 0.5, 0.25});
    const Eigen::Isometry3d t1 = Eigen::Translation3d(3, -2, 5) * Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized());
    const Eigen::Isometry3d t2 = Eigen::Translation3d(-1, 0, 2) * Eigen::AngleAxisd(-1.1, Eigen::Vector3d(0, 1, 1).normalized());
    ConvexPolyhedron once = rest;
    once.moveTo(rest, t1);
    for (const ConvexPolyhedron* from : {&rest, static_cast<const ConvexPolyhedron*>(&once)}) {
        ConvexPolyhedron copied = *from;
        copied.moveTo(*from, t2);
        const ConvexPolyhedron moved = from->moved(t2);
        EXPECT_TRUE(sameBytes(moved.vertices(), copied.vertices()));
        EXPECT_EQ(moved.faces(), copied.faces());
        EXPECT_EQ(moved.globalIds(), copied.globalIds());
        ASSERT_EQ(moved.planes().size(), copied.planes().size());
        for (size_t f = 0; f < moved.planes().size(); ++f) {
            EXPECT_TRUE(sameBytes(moved.planes()[f].normal, copied.planes()[f].normal)) << f;
            EXPECT_TRUE(shatter::test::sameBits(moved.planes()[f].offset, copied.planes()[f].offset)) << f;
        }
        EXPECT_TRUE(sameBytes(moved.bounds().min, copied.bounds().min));
        EXPECT_TRUE(sameBytes(moved.bounds().max, copied.bounds().max));
        EXPECT_TRUE(sameBytes(moved.centerOfMass(), copied.centerOfMass()));
        EXPECT_TRUE(sameBytes(moved.massProperties(700.0).inertia, copied.massProperties(700.0).inertia));
        EXPECT_TRUE(shatter::test::sameBits(moved.massProperties(700.0).mass, copied.massProperties(700.0).mass));
    }
}

// The inertia (density 1) as it was computed before only the second moment's upper entries were
// summed (whole outer products, Eigen's expression), to check the six-entry sum's bits.
static Eigen::Matrix3d inertiaByOuterProducts(const std::vector<Eigen::Vector3d>& vertices,
                                              const std::vector<std::vector<int>>& faces) {
    const Eigen::Vector3d r = vertices.front();
    double volume = 0.0;
    Eigen::Vector3d first = Eigen::Vector3d::Zero();
    Eigen::Matrix3d second = Eigen::Matrix3d::Zero();
    for (const auto& face : faces) {
        const Eigen::Vector3d a = vertices[face[0]] - r;
        for (size_t k = 1; k + 1 < face.size(); ++k) {
            const Eigen::Vector3d b = vertices[face[k]] - r, c = vertices[face[k + 1]] - r;
            const double v = a.dot(b.cross(c)) / 6.0;
            const Eigen::Vector3d s = a + b + c;
            volume += v;
            first += v / 4.0 * s;
            second += v / 20.0 * (a * a.transpose() + b * b.transpose() + c * c.transpose() + s * s.transpose());
        }
    }
    const Eigen::Vector3d cRel = first / volume;
    const Eigen::Matrix3d covariance = 1.0 * (second - volume * cRel * cRel.transpose());
    return covariance.trace() * Eigen::Matrix3d::Identity() - covariance;
}

// A polyhedron keeps its faces in one flat buffer (FaceList): read back, they are the faces it
// was given, in order, with their sizes (a prism: two triangles and three quads), and the mass
// properties over them are those of the same faces as a list of vectors; the inertia is the one
// the whole outer products give, bit for bit (only its six upper entries are summed now).
TEST(ConvexPolyhedron, FacesInOneBufferAreTheFacesItWasGiven) {
    const double a = 0.6, b = 0.3, L = 2.0;
    const std::vector<Eigen::Vector3d> v = {{0.1, 0, 0}, {a, 0.05, 0}, {0, b, 0}, {0.1, 0, L}, {a, 0.05, L}, {0, b, L}};
    const std::vector<std::vector<int>> f = {{0, 2, 1}, {3, 4, 5}, {0, 1, 4, 3}, {1, 2, 5, 4}, {2, 0, 3, 5}};
    const ConvexPolyhedron p = ConvexPolyhedron::create(v, f, {0, 1, 2, 3, 4, 5}, "prism");
    ASSERT_EQ(p.faces().size(), f.size());
    size_t k = 0;
    for (const auto face : p.faces()) {
        ASSERT_EQ(face.size(), f[k].size()) << "face " << k;
        for (size_t i = 0; i < face.size(); ++i) EXPECT_EQ(face[i], f[k][i]) << "face " << k;
        EXPECT_EQ(newellNormal(v, face), newellNormal(v, f[k]));
        ++k;
    }
    EXPECT_EQ(k, f.size());
    EXPECT_TRUE(p.faces() == FaceList(f));
    EXPECT_FALSE(p.faces() == FaceList(std::vector<std::vector<int>>(f.begin(), f.end() - 1)));

    const MassProperties flat = polyhedronMassProperties(v, p.faces(), 1.0);
    const MassProperties nested = polyhedronMassProperties(v, f, 1.0);
    EXPECT_EQ(flat.volume, nested.volume);
    EXPECT_EQ(flat.centerOfMass, nested.centerOfMass);
    EXPECT_EQ(flat.inertia, nested.inertia);
    EXPECT_EQ(flat.inertia, inertiaByOuterProducts(v, f));
    EXPECT_NEAR(flat.volume, 0.5 * ((a - 0.1) * b + 0.1 * 0.05) * L, 1e-12); // |cross of the base edges| / 2 · L
}

// A face of the list added to it again is copied before the buffer can move (inserting a
// vector's own elements is undefined once it reallocates), and the list works with <algorithm>.
TEST(FaceList, AddingOneOfItsOwnFacesCopiesIt) {
    FaceList faces(std::vector<std::vector<int>>{{0, 1, 2}, {3, 4, 5, 6}});
    for (int round = 0; round < 6; ++round) faces.add(faces[1]); // grows past its capacity
    ASSERT_EQ(faces.size(), 8u);
    for (size_t f = 1; f < faces.size(); ++f) EXPECT_TRUE(std::ranges::equal(faces[f], std::vector<int>{3, 4, 5, 6}));
    EXPECT_EQ(std::count_if(faces.begin(), faces.end(), [](std::span<const int> face) { return face.size() == 3; }), 1);
}

// Copies share the faces, which no one edits: a copy, moved() and withGlobalIds()
// read the very buffer of the original (no allocation per copy: the 64-cell break of the 16k
// shell copies thousands of primitives), the faces outlive the original, and a
// default-constructed or moved-from polyhedron has none.
TEST(ConvexPolyhedron, CopiesShareTheirFacesAndKeepThemWhenTheOriginalGoes) {
    auto original = std::make_unique<ConvexPolyhedron>(box({-1, -0.5, -0.25}, {1, 0.5, 0.25}));
    const FaceList faces = original->faces(); // a deep copy, to compare with
    const int* buffer = original->faces().indices().data();
    const ConvexPolyhedron copy = *original;
    const ConvexPolyhedron moved = original->moved(Eigen::Isometry3d(Eigen::Translation3d(1, 2, 3)));
    const ConvexPolyhedron renamed = original->withGlobalIds({10, 11, 12, 13, 14, 15, 16, 17});
    for (const ConvexPolyhedron* p : {&copy, &moved, &renamed}) {
        EXPECT_EQ(p->faces().indices().data(), buffer);
        EXPECT_TRUE(p->faces() == faces);
    }
    ConvexPolyhedron taken = std::move(*original);
    EXPECT_TRUE(original->faces().empty()); // moved from
    original.reset();
    EXPECT_TRUE(taken.faces() == faces);
    EXPECT_TRUE(moved.faces() == faces);
    EXPECT_EQ(moved.faces().indices().data(), buffer);
    EXPECT_TRUE(ConvexPolyhedron().faces().empty());
    EXPECT_EQ(ConvexPolyhedron().faces().size(), 0u);
}
