#pragma once
// What every break of a body reads of its visual surface (FragmentSurface): the directed
// visual edges listed by their first vertex, whether the surface is closed, and how many
// primitives each face is the source of. A body that breaks again and again keeps one and
// patches it by each break's RemainderEdit: built per break it was ~64 K corners of a
// 16,000-face shell (1.9 M of a ~54 M-instruction break, and ~190 of the ~850 page faults of
// a first break in a fresh process).
#include <shatter/plugin/fracture/RemainderEdit.h>
#include <shatter/plugin/geometry/PhysicalMesh.h>

#include <vector>

namespace shatter::fracture {

class SurfaceIndex {
public:
    struct Edge {
        int to;   // b of the directed visual edge a→b
        int face; // the body face it belongs to
        int next; // the next edge from a (in face order), or -1
    };

    explicit SurfaceIndex(const geometry::PhysicalMesh& body);

    // Follows applyRemainderEdit(body, edit): call it with the body as it is BEFORE the edit
    // (the dropped and moved faces are read there). Costs the edit's faces (dropped, moved,
    // gained) and source-face changes, not the body's.
    void patch(const geometry::PhysicalMesh& body, const RemainderEdit& edit);

    // Whether it was built for a body of this many visual vertices and faces (the cheap check
    // a break makes before trusting it).
    bool fits(const geometry::PhysicalMesh& body) const {
        return visualCount() == int(body.visual.positions.size()) && faceCount() == int(body.visual.faces.size());
    }
    int visualCount() const { return int(firstEdge_.size()); }
    int faceCount() const { return int(primitivesOfFace_.size()); }
    // Every edge used as often one way as the other (and some edge at all). Found at the
    // first call after a build or patch, by a pass that stops at the first edge used more
    // often one way (an open body's first few edges; a patch of an open body that a break
    // left open then costs nothing like the full pass).
    bool closed() const;

    // The edges from a, in face order: firstEdge(a), then edge(e).next until -1.
    int firstEdge(int a) const { return firstEdge_[size_t(a)]; }
    const Edge& edge(int e) const { return edges_[size_t(e)]; }
    // How many faces hold the directed edge a→b; the first of them in face order, or -1.
    int edgeCount(int a, int b) const;
    int faceWithEdge(int a, int b) const;
    // Body primitives whose source face is `face`.
    int primitivesOf(int face) const { return primitivesOfFace_[size_t(face)]; }

    // Same lists (each vertex's edges, their ends and faces, in order), closedness and
    // source-face counts: a patched index equals the one built from the edited body.
    bool operator==(const SurfaceIndex& other) const;

private:
    // Face `index` (its vertex cycle) added to (taken from) the lists, each edge at its place
    // in face order.
    void addFace(const std::vector<int>& face, int index);
    void removeFace(const std::vector<int>& face, int index);
    void link(int a, int b, int face);
    void unlink(int a, int b, int face);

    std::vector<int> firstEdge_;        // per visual vertex
    std::vector<Edge> edges_;           // used ones and free ones (a list from freeEdge_)
    int freeEdge_ = -1;
    int edgeCount_ = 0;                 // in use
    enum class Closed : char { Unknown, No, Yes };
    mutable Closed closed_ = Closed::Unknown; // see closed()
    std::vector<int> primitivesOfFace_; // per body face
};

} // namespace shatter::fracture
