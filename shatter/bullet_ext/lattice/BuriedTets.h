#pragma once
// The tets of a lattice piece that nothing can touch: those with no corner on the piece's
// surface (outer and crack faces). Every such tet lies inside the piece, wrapped by tets that
// do have a corner there, so a body outside reaches it only by sinking into them deeper than
// any contact reaches (a tet's contact breaking threshold, under a millimetre, against a
// layer of tets some centimetres thick). Yet their boxes overlap those of the outer layer,
// and the group shape's contact algorithms ran Bullet's separating-axis test on every one of
// them near a piece of debris: skipping them (GroupShape::setBuried,
// LatticeSettings::skipBuriedTets) leaves the same contacts at a fraction of the tests.
#include <shatter/plugin/geometry/PhysicalMesh.h>

#include <vector>

namespace shatter {

class VisualBody;

// One flag per primitive of `mesh`: 1 when none of its corners (global ids) is a corner of
// one of the mesh's visual faces.
std::vector<char> buriedPrimitives(const geometry::PhysicalMesh& mesh);

// Flags the buried tets of `body`'s physical mesh in its collision shape, when that is its
// group shape (a convex piece collides as its hull, with no leaves to skip).
void markBuriedTets(VisualBody& body);

} // namespace shatter
