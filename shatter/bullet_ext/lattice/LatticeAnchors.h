#pragma once
// Which tets of a new lattice body are anchored (LatticeSettings::fixedTets, anchorRegions,
// anchorTo): regions in mesh or world coordinates and contact with static Bullet bodies are
// turned into one explicit list where the body is created.
#include <shatter/bullet_ext/lattice/LatticeSettings.h>
#include <shatter/plugin/lattice/TetMesh.h>

#include <BulletCollision/CollisionDispatch/btCollisionWorld.h>

#include <vector>

namespace shatter {

// The tets within `distance` (m) of the static body `anchor` when the mesh is placed at `pose`
// (mesh to world), by Bullet's own contact query on each tet near the body's box.
std::vector<int> tetsTouching(const lattice::TetMesh& mesh, const btTransform& pose, const btCollisionObject& anchor,
                              double distance, btCollisionWorld& world);

// `settings` with fixedTets the sorted union of its list, its regions and the tets touching
// its anchorTo bodies; anchorRegions and anchorTo emptied. Throws shatter::InputError naming
// the body for a bad mesh (only checked here when regions or bodies are given), a non-finite
// pose, a null or non-static anchor body, or a region or body that anchors no tet.
LatticeSettings resolveAnchors(const lattice::TetMesh& mesh, const LatticeSettings& settings, const btTransform& pose,
                               btCollisionWorld& world);

} // namespace shatter
