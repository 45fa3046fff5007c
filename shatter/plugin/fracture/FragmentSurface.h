#pragma once
// The visual surface of a fragment (source 000 §3.4, §3.6): the body's own surface inside it
// plus the crack faces, in fracture-wide global ids.
#include <shatter/plugin/fracture/Solid.h>
#include <shatter/plugin/fracture/SurfaceIndex.h>
#include <shatter/plugin/geometry/PhysicalMesh.h>

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <vector>

namespace shatter::fracture {

// One primitive of a fragment: a body primitive moved whole, or a cut piece.
struct FragmentPart {
    int parent = -1;             // body primitive
    std::optional<CutFaces> cut; // the piece's faces and their kinds; none when moved whole
    // A whole primitive that stays in the body (the rest edited in place) and lost its source
    // face: only its own parts of that face, the body keeps its other faces.
    bool sourceOnly = false;
};

struct FragmentFaces {
    std::vector<std::vector<int>> faces; // fracture-wide global ids
    std::vector<bool> crack;
    // Per part: index in `faces` of its body face kept whole, or -1; every part made from a
    // face of several primitives points at it, so a later break knows all of them.
    std::vector<int> sourceFace;
};

class FragmentSurface {
public:
    // `index`: the body's SurfaceIndex kept between breaks (it must fit the body), or null to
    // build one for this break.
    explicit FragmentSurface(const geometry::PhysicalMesh& body, const SurfaceIndex* index = nullptr);

    // Whether the body's visual surface is closed (every edge used as often one way as the
    // other). Then the fragments show the inner side of extruded faces too, and their surfaces
    // are closed: what was inside the body's surface is open to view after the break.
    bool closed() const { return index_->closed(); }

    // The fragment's faces: faces of the body kept whole where all primitives made from them
    // are whole in this fragment, the visual faces of cut pieces, their crack faces, the faces
    // the body shows as a primitive's own (a fragment of a closed body shows its primitives'
    // inner faces), and for a closed body the hidden faces; faces that meet a face of the same
    // fragment back to back (same ids, opposite winding) are inside it and left out.
    FragmentFaces build(const std::vector<FragmentPart>& parts);

    // Body primitives whose source face is `face`.
    int primitivesOf(int face) const { return index_->primitivesOf(face); }
    // The body's visual face with this id cycle, read the same way round (from any start), or -1.
    int shownFace(std::span<const int> ids) const;
    int shownFace(const std::vector<int>& ids) const { return shownFace(std::span<const int>(ids)); }
    // What a face (its id cycle) of a body primitive is on the body's surface: Visual when it
    // is part of the primitive's source face or a face the body shows, else Hidden. (Not
    // "all its ids are visual": a fragment of a closed body shows its primitives' inner
    // faces, so their ids are visual, yet the faces between two of its primitives are inside.)
    FaceKind kindOf(int primitive, std::span<const int> ids) const;

private:
    // Whether every id of the face is one of the primitive's source face's: its part of the
    // face it was extruded from (the whole face, or a triangle of a polygon split into several).
    bool onSourceFace(int primitive, std::span<const int> ids) const;
    // Whether a hidden face of a whole prism meets its twin back to back in this fragment:
    // a side face over an edge whose other prism is also whole here (the inner side of the
    // shell continues). Decided from the body's faces, without hashing.
    bool sideFaceInside(std::span<const int> face, int source) const;
    bool faceWholeHere(int face) const {
        return index_->primitivesOf(face) > 0 && wholeCount_[size_t(face)] == index_->primitivesOf(face);
    }
    // Counts the whole parts per source face and reserves the lists (see build).
    void prepare(const std::vector<FragmentPart>& parts, FragmentFaces& out);
    void emitCut(const CutFaces& s, bool closedBody, FragmentFaces& out);
    void emitWhole(const FragmentPart& part, bool closedBody, int& sourceFace, FragmentFaces& out);
    struct WholePart {
        int parent, source;  // the body primitive and its source face (or -1)
        bool sourceOnly;     // FragmentPart::sourceOnly
        bool faceWhole;      // every primitive of its source face is whole in this fragment
    };
    // A face of a whole part with its ids: shown or not, and how.
    void emitWholeFace(const WholePart& whole, std::span<const int> ids, bool allVisual, bool closedBody,
                       FragmentFaces& out);
    // The first n values of ids_, grown to hold them (never shrunk: resizing it to each
    // face's size, 3 then 4 then 3, zero-filled an element at every growth; with the one
    // emit for every face, ~0.03 M instructions less in five events of the 16k shell).
    std::span<int> idBuffer(size_t n) {
        if (ids_.size() < n) ids_.resize(n);
        return {ids_.data(), n};
    }
    // Appends the face; a cancellable one is listed in keys_ for cancelBackToBack.
    void emit(std::span<const int> face, bool crack, bool cancellable, FragmentFaces& out);
    void cancelBackToBack(FragmentFaces& out);
    // Lists each key under its hash: every hash's keys in one run, in face order.
    void groupKeysByHash();
    void cancelWithin(const std::vector<int>& run, const FragmentFaces& out);
    void dropCancelled(FragmentFaces& out);

    const geometry::PhysicalMesh& body_;
    int visualCount_;
    std::optional<SurfaceIndex> own_; // when no index was given
    const SurfaceIndex* index_;       // the body's edges by first vertex, closedness, source-face counts
    std::vector<int> wholeCount_;       // per body face: whole ones in the current fragment
    std::vector<int> emittedIn_;        // per body face: fragment serial that emitted it
    // Per body face: its index in that fragment's faces; read only where emittedIn_ is the
    // current serial, so left uninitialised (filling it was ~64 k instructions a break).
    std::unique_ptr<int[]> emittedAt_;
    int serial_ = 0;
    std::vector<int> ids_; // scratch: the face being read
    // A cancellable face of the current fragment: a hash of its id set (the same for every
    // reading of the cycle, either way round), so a face and its reverse share one.
    struct FaceKey {
        std::uint64_t hash;
        int face;
        int nextSame; // the next key (in face order) of the same hash, or -1
        int lastSame; // of a run's first key: its last key
        bool gone;    // cancelled
    };
    std::vector<FaceKey> keys_;
    std::vector<int> slots_;      // open addressing: the first key of each hash, or -1
    std::vector<int> sharedRuns_; // first keys of the hashes that several keys have
    std::vector<int> run_;        // scratch: the keys of one hash, in face order
    std::vector<int> cancelled_;  // faces of the current fragment that met their reverse
};

} // namespace shatter::fracture
