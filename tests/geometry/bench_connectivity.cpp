// Timing of physical-mesh creation and connectivity on large surfaces (not a test: run
// by hand, Release build). Usage: shatter_bench_connectivity [nx ny]
#include <shatter/plugin/geometry/Connectivity.h>
#include <shatter/plugin/geometry/PhysicalMesh.h>

#include "MeshFixtures.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>

using namespace shatter::geometry;

namespace {

double secondsSince(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

void run(const char* what, const shatter::test::FaceMesh& m) {
    auto start = std::chrono::steady_clock::now();
    const PhysicalMesh mesh = buildPhysicalMesh(what, m.positions, m.faces);
    const double build = secondsSince(start);
    start = std::chrono::steady_clock::now();
    const auto pairs = touchingPairs(mesh.primitives, mesh.contactTolerance);
    const double connect = secondsSince(start);
    std::printf("%-28s %7zu faces %7zu primitives %8zu connections %3d components: build %.3f s, "
                "connectivity alone %.3f s\n",
                what, m.faces.size(), mesh.primitives.size(), pairs.size(), mesh.componentCount(), build, connect);
}

} // namespace

int main(int argc, char** argv) {
    const int nx = argc > 2 ? std::atoi(argv[1]) : 200;
    const int ny = argc > 2 ? std::atoi(argv[2]) : 100;
    shatter::test::FaceMesh flat = shatter::test::quadGrid(nx, ny, 0.01);
    run("flat quad grid", flat);
    // Bumpy: every quad non-planar, so each becomes two triangle prisms.
    shatter::test::FaceMesh bumpy = shatter::test::quadGrid(nx / 2, ny, 0.01);
    for (auto& p : bumpy.positions) p.z() = 0.003 * std::sin(37.0 * p.x()) * std::cos(23.0 * p.y());
    run("bumpy quad grid (triangles)", bumpy);
    return 0;
}
