#pragma once
// Planar texture coordinates for crack faces (source 000 §3.6: crack faces are drawn with a
// material of their own, the inside of the solid). A crack face is planar, so projecting it
// onto its own plane maps it without stretch.
#include <Eigen/Core>
#include <vector>

namespace shatter::fracture {

// Per vertex of `face` (indices into `positions`): its coordinates in metres along two unit
// axes of the face's plane. The axes depend on the plane's normal alone, taken up to sign
// (its largest component made positive), so every vertex of a face maps by one rule and the
// two sides of one crack (the same polygon wound opposite ways, in neighbouring fragments)
// get the same coordinates at the same points: the texture runs on across the break.
std::vector<Eigen::Vector2d> crackFaceUvs(const std::vector<Eigen::Vector3d>& positions, const std::vector<int>& face);

} // namespace shatter::fracture
