#include <shatter/plugin/lattice/TetMesh.h>

#include <shatter/plugin/common/InputError.h>
#include <shatter/plugin/lattice/TetFaces.h>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <utility>
#include <vector>

namespace shatter::lattice {

double signedVolume(const TetMesh& mesh, const Tet& t) {
    const Eigen::Vector3d& a = mesh.nodes[t[0]];
    return (mesh.nodes[t[1]] - a).dot((mesh.nodes[t[2]] - a).cross(mesh.nodes[t[3]] - a)) / 6.0;
}

Eigen::Vector3d centroid(const TetMesh& mesh, const Tet& t) {
    return 0.25 * (mesh.nodes[t[0]] + mesh.nodes[t[1]] + mesh.nodes[t[2]] + mesh.nodes[t[3]]);
}

std::string tetLabel(const TetMesh& mesh, int t) {
    const long number = t < int(mesh.tetNumbers.size()) ? mesh.tetNumbers[t] : long(t);
    return "tetrahedron " + std::to_string(number);
}

std::array<std::array<int, 3>, 4> outwardFaces(const Tet& t) {
    return {{{t[1], t[2], t[3]}, {t[0], t[3], t[2]}, {t[0], t[1], t[3]}, {t[0], t[2], t[1]}}};
}

TetMesh makeTetMesh(std::string name, std::vector<Eigen::Vector3d> nodes, std::vector<Tet> tets) {
    TetMesh mesh;
    mesh.name = std::move(name);
    mesh.nodes = std::move(nodes);
    mesh.tets = std::move(tets);
    validateTetMesh(mesh);
    return mesh;
}

namespace {

[[noreturn]] void fail(const TetMesh& mesh, const std::string& problem) {
    throw InputError(mesh.name + ": " + problem);
}


double longestEdge(const TetMesh& mesh, const Tet& t) {
    double longest = 0.0;
    for (int i = 0; i < 4; ++i)
        for (int j = i + 1; j < 4; ++j) longest = std::max(longest, (mesh.nodes[t[i]] - mesh.nodes[t[j]]).norm());
    return longest;
}

} // namespace

std::pair<int, int> duplicateTets(const TetMesh& mesh) {
    std::vector<std::pair<Tet, int>> sorted;
    sorted.reserve(mesh.tets.size());
    for (int t = 0; t < int(mesh.tets.size()); ++t) {
        Tet key = mesh.tets[t];
        std::sort(key.begin(), key.end());
        sorted.emplace_back(key, t);
    }
    std::sort(sorted.begin(), sorted.end());
    std::pair<int, int> first{-1, -1};
    for (size_t i = 1; i < sorted.size(); ++i)
        if (sorted[i].first == sorted[i - 1].first && (first.second < 0 || sorted[i].second < first.second))
            first = {sorted[i - 1].second, sorted[i].second};
    return first;
}

std::string duplicateProblem(const TetMesh& mesh, int earlier) {
    return "has the same four nodes as " + tetLabel(mesh, earlier) + " (a repeated element would double the mass there)";
}

std::string tetProblem(const TetMesh& mesh, int index) {
    const Tet& t = mesh.tets[index];
    for (int k = 0; k < 4; ++k) {
        if (t[k] < 0 || t[k] >= int(mesh.nodes.size()))
            return "uses node " + std::to_string(t[k]) + ", which does not exist (the mesh has " + std::to_string(mesh.nodes.size()) +
                   " nodes)";
        for (int j = 0; j < k; ++j)
            if (t[j] == t[k]) return "uses node " + std::to_string(t[k]) + " twice";
    }
    const double volume = signedVolume(mesh, t);
    const double edge = longestEdge(mesh, t);
    std::ostringstream msg;
    // Coordinates near 1e100 and beyond overflow the volume's products: NaN or infinite,
    // which neither the degenerate nor the inverted test below would catch.
    if (!std::isfinite(volume) || !std::isfinite(edge)) {
        msg << "has a volume that is not a finite number (volume " << volume << " m^3, longest edge " << edge
            << " m: coordinates too large for double precision)";
        return msg.str();
    }
    if (std::abs(volume) <= kDegenerateVolumeRatio * edge * edge * edge) {
        msg << "is degenerate (volume " << volume << " m^3 for a longest edge of " << edge << " m)";
        return msg.str();
    }
    if (volume < 0) {
        msg << "is inverted (signed volume " << volume << " m^3; the fourth corner must lie on the"
            << " counter-clockwise side of the first three)";
        return msg.str();
    }
    return {};
}

void validateTetMesh(const TetMesh& mesh) {
    if (mesh.nodes.empty()) fail(mesh, "has no nodes");
    if (mesh.tets.empty()) fail(mesh, "has no tetrahedra");
    for (size_t i = 0; i < mesh.nodes.size(); ++i)
        if (!mesh.nodes[i].allFinite()) fail(mesh, "node " + std::to_string(i) + " has a non-finite coordinate");
    const auto [earlier, later] = duplicateTets(mesh);
    if (later >= 0) fail(mesh, tetLabel(mesh, later) + " " + duplicateProblem(mesh, earlier));
    for (int t = 0; t < int(mesh.tets.size()); ++t) {
        const std::string problem = tetProblem(mesh, t);
        if (!problem.empty()) fail(mesh, tetLabel(mesh, t) + " " + problem);
    }
    const TetFaces faces = buildTetFaces(mesh);
    if (faces.overusedTet >= 0)
        fail(mesh, tetLabel(mesh, faces.overusedTet) + ": face " + std::to_string(faces.overusedFace) +
                       " is shared by more than two tetrahedra (the mesh is not a manifold solid)");
    std::vector<int> pieceOfTet;
    const int pieces = connectedPieces(faces, pieceOfTet);
    if (pieces > 1) {
        const auto other = std::find_if(pieceOfTet.begin(), pieceOfTet.end(), [](int p) { return p != 0; });
        fail(mesh, "is disconnected: " + std::to_string(pieces) + " pieces; " +
                       tetLabel(mesh, int(other - pieceOfTet.begin())) + " shares no chain of faces with " +
                       tetLabel(mesh, 0) + " (give each piece its own body)");
    }
}

} // namespace shatter::lattice
