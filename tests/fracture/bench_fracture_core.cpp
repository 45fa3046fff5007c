// Timing of fractureMesh alone (no Bullet), by hand: not a test.
//   bin/shatter_bench_fracture_core [repeats [primitives cells]]   (one case: 100|1000|16000, 16|64|256)
// Bodies: a closed torus shell of extruded quads with about 100, 1,000 and 16,000 primitives;
// Voronoi patterns of 16, 64 and 256 cells (2/3 of them within the radius) placed on its
// outer equator. Prints one line per case and the JSON of all cases last.
#include <shatter/plugin/fracture/FractureMesh.h>
#include <shatter/plugin/geometry/PhysicalMeshBuilder.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <numbers>
#include <string>
#include <vector>

using namespace shatter;

namespace {

// Torus of radii 1 and 0.35 m with nu × nv quads, outward, extruded by 1 cm.
geometry::PhysicalMesh torus(int nu, int nv) {
    std::vector<Eigen::Vector3d> positions;
    std::vector<std::vector<int>> faces;
    for (int i = 0; i < nu; ++i)
        for (int j = 0; j < nv; ++j) {
            const double u = 2.0 * std::numbers::pi * i / nu, v = 2.0 * std::numbers::pi * j / nv;
            const double r = 1.0 + 0.35 * std::cos(v);
            positions.emplace_back(r * std::cos(u), r * std::sin(u), 0.35 * std::sin(v));
        }
    auto at = [&](int i, int j) { return ((i + nu) % nu) * nv + (j + nv) % nv; };
    for (int i = 0; i < nu; ++i)
        for (int j = 0; j < nv; ++j) faces.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)});
    geometry::PhysicalMeshSettings s;
    s.thickness = 0.01;
    return geometry::buildPhysicalMesh("torus", positions, faces, s);
}

struct Stats {
    double median, p99, worst;
};
Stats stats(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    auto at = [&](double q) { return v[std::min(v.size() - 1, size_t(q * double(v.size() - 1) + 0.5))]; };
    return {at(0.5), at(0.99), v.back()};
}

} // namespace

int main(int argc, char** argv) {
    const int repeats = argc > 1 ? std::atoi(argv[1]) : 15;
    std::vector<std::pair<int, int>> sizes{{10, 10}, {40, 25}, {160, 100}};
    std::vector<int> cellCounts{16, 64, 256};
    if (argc > 3) { // one case only (for callgrind)
        const int n = std::atoi(argv[2]);
        sizes = {n <= 100 ? sizes[0] : n <= 1000 ? sizes[1] : sizes[2]};
        cellCounts = {std::atoi(argv[3])};
    }
    std::string json = "{\"cases\":[";
    bool first = true;
    for (const auto& [nu, nv] : sizes) {
        const auto body = torus(nu, nv);
        for (int cells : cellCounts) {
            fracture::VoronoiPatternSettings ps;
            ps.cells = cells;
            ps.radius = 0.4;
            const auto pattern = fracture::voronoiPattern(ps, 1);
            fracture::Placement where;
            where.point = {1.35, 0.0, 0.0};
            where.normal = {-1.0, 0.0, 0.0};
            std::vector<double> total, cutting, islands, assembly;
            fracture::FractureResult r;
            for (int k = 0; k < repeats; ++k) {
                where.twist = fracture::seededTwist(std::uint64_t(k));
                const auto t0 = std::chrono::steady_clock::now();
                r = fracture::fractureMesh(body, pattern, where, fracture::CutSettings{});
                total.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() * 1e3);
                cutting.push_back((r.seconds.placement + r.seconds.cutting) * 1e3);
                islands.push_back(r.seconds.islands * 1e3);
                assembly.push_back(r.seconds.assembly * 1e3);
            }
            const Stats t = stats(total), c = stats(cutting), i = stats(islands), a = stats(assembly);
            std::printf("%6zu primitives, %3d cells: %zu pieces, %d cut; ms median %.3f p99 %.3f worst %.3f "
                        "(placement+cutting %.3f, islands %.3f, assembly %.3f medians)\n",
                        body.primitives.size(), cells, r.pieces.size(), r.primitivesCut, t.median, t.p99, t.worst,
                        c.median, i.median, a.median);
            char buffer[512];
            std::snprintf(buffer, sizeof buffer,
                          "%s{\"primitives\":%zu,\"cells\":%d,\"pieces\":%zu,\"cut\":%d,\"ms_median\":%.4f,"
                          "\"ms_p99\":%.4f,\"ms_worst\":%.4f,\"ms_cutting\":%.4f,\"ms_islands\":%.4f,"
                          "\"ms_assembly\":%.4f}",
                          first ? "" : ",", body.primitives.size(), cells, r.pieces.size(), r.primitivesCut, t.median,
                          t.p99, t.worst, c.median, i.median, a.median);
            json += buffer;
            first = false;
        }
    }
    std::printf("%s]}\n", json.c_str());
}
