#pragma once
// A bounding-box tree over a body's primitives that the body keeps between breaks (its
// collision shape's tree, edited with the rest), so that a break finds the primitives its
// cells may reach without reading every primitive of the body; and its surface index.
#include <shatter/plugin/geometry/AabbTree.h>

#include <Eigen/Geometry>

namespace shatter::fracture {

class SurfaceIndex;

struct PrimitiveIndex {
    // Item i's box holds primitive i of the body, in the tree's frame (up to round-off: a
    // break widens the boxes by a relative 1e-9 before it trusts them). Null: no index, the
    // break tests every primitive's box.
    const geometry::AabbTree* tree = nullptr;
    // The tree's frame → the body's rest (mesh) coordinates.
    Eigen::Isometry3d treeToMesh = Eigen::Isometry3d::Identity();
    // The body's surface index, kept between breaks and patched by each break's RemainderEdit
    // (SurfaceIndex::patch), or null: the break builds one. It must fit the body
    // (SurfaceIndex::fits, checked) and be the one built from it (not checked: the keeper's).
    const SurfaceIndex* surface = nullptr;
};

} // namespace shatter::fracture
