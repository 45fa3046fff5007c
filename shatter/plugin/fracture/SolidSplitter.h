#pragma once
// Convex half-space clipping (source 000 §3.6, "cut-intersecting primitives"): splits a
// convex solid by a plane into the part below it and the part above it, and closes both
// with the same cut face (a crack face), wound opposite ways.
#include <shatter/plugin/fracture/NewVertexIds.h>
#include <shatter/plugin/fracture/Solid.h>

namespace shatter::fracture {

class SolidSplitter {
public:
    enum class Outcome {
        Below, // nothing above the plane: the solid is unchanged (no output written)
        Above, // nothing below
        Split, // both outputs written
    };

    // Plane n·x = d. A vertex within `tolerance` of the plane counts as on it: the cut passes
    // through it and no new vertex is made within the tolerance of an existing one (the
    // snap). New vertices get their ids from `ids`. `above` may be null when only the part
    // below is wanted. Reuses its scratch space: no allocation once warmed up.
    Outcome split(const Solid& solid, const Eigen::Vector3d& n, double d, double tolerance, NewVertexIds& ids,
                  Solid& below, Solid* above);

    // (Public for the file's crossing finder.)
    struct Crossing {
        int b;    // the edge's higher vertex index (the lower one's lastFrom_ chain holds it)
        int next; // the crossing before it from the same lower vertex, or -1
    };

private:
    // The vertices' distances (distance_) and sides (side_); Below or Above when all are on
    // that side (or on the plane), Split when both sides have some.
    Outcome measure(const Solid& solid, const Eigen::Vector3d& n, double d, double tolerance);
    // Writes the part below (gathering its cut-face edges) and, with kAbove, the part above
    // in the same pass over the faces, finding the edges the plane crosses on the way, in the
    // order the faces meet them (that order numbers the new vertices, newPositions_); vertex
    // sources are old vertex indices, then count + crossing index. The new vertices' ids are
    // left to the caller.
    template <bool kAbove>
    void writeParts(const Solid& solid, Solid& below, Solid* above);
    // The new vertices' ids, written where each part has them (count: the solid's vertices).
    void assignIds(NewVertexIds& ids, int count, Solid& below, Solid* above) const;
    // The cut face of the part below (cap_) from capEdges_, when they make one simple loop.
    bool chainCap(int vertexCount);
    // Closes the parts with the cut face (reversed on the part above).
    void closeParts(Solid& below, Solid* above) const;

    std::vector<double> distance_;
    std::vector<signed char> side_;
    // Room (one per face-vertex slot, only grows), not the count: the crossings are the first
    // newPositions_.size() entries.
    std::vector<Crossing> crossings_;
    std::vector<int> lastFrom_;     // per vertex: its last crossing to a higher index, or -1
    std::vector<Eigen::Vector3d> newPositions_;
    std::vector<int> mapBelow_, mapAbove_; // vertex source → index in the part, or -1
    std::vector<int> sourceBelow_;         // index in the part below → vertex source
    std::vector<std::pair<int, int>> capEdges_; // directed cut-face edges of the part below
    std::vector<int> cap_;                      // cut face of the part below (its indices)
    std::vector<int> capNext_;                  // per vertex of the part below: its cut-face edge's end, or -1
};

} // namespace shatter::fracture
