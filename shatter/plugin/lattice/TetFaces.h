#pragma once
// Which tets share which faces: the adjacency the lattice's links are made from.
#include <shatter/plugin/lattice/TetMesh.h>

#include <array>
#include <vector>

namespace shatter::lattice {

struct SharedFace {
    int tetA = -1, tetB = -1;        // tetA < tetB
    std::array<int, 3> nodes{};      // counter-clockwise seen from tetA's side looking out
};

struct TetFaces {
    std::vector<SharedFace> shared;               // in order of (tetA, local face) found
    std::vector<std::array<int, 4>> neighbour;    // per tet, per face (opposite corner k): tet or -1
    int boundaryCount = 0;                        // faces with no neighbour
    // A face used by more than two tets (a non-manifold mesh), or -1 if none: tet and local face.
    int overusedTet = -1, overusedFace = -1;
};

// Faces are matched by their sorted node triples; O(tets log tets), deterministic.
TetFaces buildTetFaces(const TetMesh& mesh);

// Number of pieces of the tet graph (tets joined by shared faces) and, per tet, its piece
// (pieces numbered by their lowest tet).
int connectedPieces(const TetFaces& faces, std::vector<int>& pieceOfTet);

} // namespace shatter::lattice
